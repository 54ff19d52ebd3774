/* cmds.h -- the disim subcommands and the helpers they share.
 *
 * Each subcommand is int cmd_NAME(argc, argv), argv[0] being the
 * subcommand's name; exit status 0 ok, 1 failure or bad input, 2 usage.
 * A subcommand parses its flags and calls the libraries; what it prints
 * goes through the helpers below. */
#ifndef DISIM_APP_CMDS_H
#define DISIM_APP_CMDS_H

#include "sim_scenario.h"

#include <stddef.h>

int cmd_check(int argc, char **argv);    /* cmd_check.c */
int cmd_trim(int argc, char **argv);     /* cmd_trim.c */
int cmd_render(int argc, char **argv);   /* cmd_render.c */
int cmd_airwake(int argc, char **argv);  /* cmd_airwake.c */
int cmd_probe(int argc, char **argv);    /* cmd_airwake.c */
int cmd_validate(int argc, char **argv); /* cmd_airwake.c */
int cmd_airwaked(int argc, char **argv); /* cmd_airwaked.c */
int cmd_fly(int argc, char **argv);      /* cmd_fly.c */
int cmd_shol(int argc, char **argv);     /* cmd_shol.c */
int cmd_station(int argc, char **argv);  /* cmd_station.c */
int cmd_ios(int argc, char **argv);      /* cmd_ios.c */

/* ------------------------------------------------------------ log (log.c) */
/* The libraries' log on standard error: "PREFIX: LEVEL: message", the
 * level's name in words ("error", "warning", "info", "debug"). On a
 * terminal (tty set) the line first clears a progress line being
 * rewritten in place. A core_log callback; user is an app_log. */
typedef struct app_log {
    const char *prefix; /* e.g. "shol"; NULL or "": none */
    int tty;            /* 1: standard error is a terminal */
} app_log;
void app_log_stderr(void *user, int level, const char *msg);

/* -------------------------------------------------------- flags (log.c) */
/* A number flag's value in [lo, hi]: 0, or -1 after printing
 * "PREFIX: FLAG: expected a number from LO to HI, got 'S'". */
int app_parse_double(const char *prefix, const char *flag, const char *s, double lo, double hi, double *out);
/* The same for a whole number. */
int app_parse_int(const char *prefix, const char *flag, const char *s, int lo, int hi, int *out);

/* --------------------------------------------- builder launch (launch.c) */
/* Starting `disim airwaked DB --exit-when-idle --no-lcm --ships DIR
 * [--max-iter N]` in the background when no builder serves a database
 * (an awdb_fields_opts.launch; user is an app_launcher), its output into
 * DB/builder.log, in a session of its own so that it outlives this
 * process if another client still waits on it. */
typedef struct app_launcher {
    char exe[4096];       /* this disim executable ("" : cannot launch) */
    char ships_dir[1024]; /* the ships folder the builder looks ships up in */
    char aircraft_dir[1024]; /* the OpenFOAM engine's aircraft folder (the loaded rotor's blades) */
    int max_iter;         /* > 0: the builder's CFD iteration limit */
    int foam_np;          /* > 0: the OpenFOAM engine with this many MPI ranks; 0: the embedded one */
    long pid;             /* the last builder started (0: none) */
} app_launcher;
/* Fill l for the scenario's ship and aircraft files' folders and its
 * engine; 0, or -1 when this executable's path cannot be found. */
int app_launcher_init(app_launcher *l, const sim_scenario *sc, int max_iter);
/* The airwake database a scenario's runs use unless --db names one: one
 * folder per engine (a database holds one engine's fields). */
const char *app_db_default(const sim_scenario *sc);
int app_launch_builder(void *user, const char *db_dir);

/* ------------------------------------------- ranks of a sweep (ranks.c) */
/* Where this process stands in a sweep spread over several processes
 * (docs/cluster.md): rank and ranks from the launcher's environment
 * (OMPI_COMM_WORLD_RANK/SIZE under Open MPI's mpirun, PMI_RANK/PMI_SIZE
 * under MPICH's, SLURM_PROCID/SLURM_STEP_NUM_TASKS under srun), 0 of 1
 * without one; run_id (n bytes) the launcher's job, so that parts of one
 * run are kept apart from another's (PMIX_NAMESPACE, SLURM_JOB_ID and
 * SLURM_STEP_ID; "" without one), with only [A-Za-z0-9._-] kept. 0, or
 * -1 after a message naming a variable that is not a rank. */
int app_ranks_from_env(int *rank, int *ranks, char *run_id, size_t n);

/* A run's scene for the renderer (scene.c): app_scene_open,
 * app_render_state_from_flight, ... are declared in scene.h. */

#endif

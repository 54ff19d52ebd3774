/* sim_ios.h -- the instructor's console (sim/ios.c): commands typed as
 * text, sent to the flight loop as sim_control_t on DISIM_SIM_CONTROL,
 * answered from its sim_status_t on DISIM_SIM_STATUS.
 * Part of sim.h (the umbrella header). */
#ifndef DISIM_SIM_IOS_H
#define DISIM_SIM_IOS_H

#include "core.h"
#include "sim_scenario.h"

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* What a line asks: a sim_control_t command (lcm_types/sim_control_t.lcm,
 * 1 pause to 12 restore) with its fields, or one of the console's own. */
enum {
    SIM_IOS_NONE = 100, /* a blank line or a # comment */
    SIM_IOS_STATUS,     /* the loop's next status, shown */
    SIM_IOS_WAIT,       /* wait wait_s (scripts) */
    SIM_IOS_HELP,
    SIM_IOS_QUIT
};
typedef struct sim_ios_cmd {
    int command;
    double pos_S_m[3];  /* reposition: the CG from the spot in S, m (x bow, y starboard, z down) */
    double heading_rad; /* reset deck, reposition (NAN: not given) */
    double wod_speed_mps, wod_dir_rad;
    int sea_state, turbulence;
    char name[32];      /* snap, restore */
    char path[SIM_PATH_MAX]; /* load */
    double wait_s;
} sim_ios_cmd;
/* One line:
 *   freeze | pause            resume | unfreeze
 *   reset                     reset hover | reset deck [HDG_DEG]
 *   reposition X Y Z [HDG_DEG]  (m in S from the landing spot, z down)
 *   wod KT DIR_DEG            sea N            turb on|off
 *   snap NAME | snapshot NAME restore NAME     load SCENARIO
 *   status   wait S   help   quit
 * 0 with cmd, or -1 with err saying what was expected. Numbers are read
 * as typed (a NaN too): the loop checks them and says why it refuses. */
int sim_ios_parse(const char *line, sim_ios_cmd *cmd, core_err *err);
/* A sim_control_t command (1 pause .. 12 restore) in words ("reset
 * hover", "set wod"); "?" for another. */
const char *sim_ios_command_name(int command);
/* The commands, one a line, for help. */
const char *sim_ios_help(void);

/* The console's LCM side. */
typedef struct sim_ios sim_ios;
/* NULL with err (the URL cannot be opened). lcm_url NULL: the library's default. */
sim_ios *sim_ios_create(const char *lcm_url, core_err *err);
void sim_ios_destroy(sim_ios *io);
/* An answer: the status that carried it. */
typedef struct sim_ios_answer {
    long long seq;          /* the control answered (-1: none) */
    int command, result;    /* result: sim_status_t CONTROL_* (1 accepted, 2 refused) */
    char message[256];      /* what was done, or why not */
    double apply_s;         /* wall time its application took */
    int state;              /* sim_status_t RUNNING, PAUSED, STOPPED */
    double sim_time_s, rate_hz, real_time_factor;
    char scenario[64];
    unsigned flags;         /* sim_status_t FLAG_* */
    int n_stations;
    char active_id[64];     /* the station flying ("" none) */
    long long control_refused;
} sim_ios_answer;
/* Send a control (cmd->command 1-12) with a seq of its own (the wall
 * clock's microseconds, rising) and wait up to timeout_s for the status
 * that answers it: 0 accepted, 1 refused (a->message says why), -1 with
 * err (no answer in time, LCM failed). */
int sim_ios_send(sim_ios *io, const sim_ios_cmd *cmd, double timeout_s, sim_ios_answer *a, core_err *err);
/* The next status within timeout_s: 0, or -1 with err. */
int sim_ios_status(sim_ios *io, double timeout_s, sim_ios_answer *a, core_err *err);
/* An answer (status 0) or a status (status 1) in one line of text. */
void sim_ios_format(const sim_ios_answer *a, int status, char *buf, size_t n);

#ifdef __cplusplus
}
#endif

#endif

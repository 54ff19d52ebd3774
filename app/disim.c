/* disim.c -- the disim command: a thin dispatcher over the libraries. Each
 * subcommand parses its flags, calls one library entry point and maps its
 * return code to the exit status (0 ok, 1 bad input or failure). */
#include "cmds.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

typedef int (*cmd_fn)(int argc, char **argv);

static int cmd_help(int argc, char **argv);

static const struct {
    const char *name;
    cmd_fn fn;
    const char *usage;
} cmds[] = {
    {"help", cmd_help, "help                      this text"},
    {"check", cmd_check, "check FILE                check a scenario, aircraft or ship file fully, print it"},
#ifdef DISIM_HAVE_HFM
    {"trim", cmd_trim, "trim AIRCRAFT             trim sweep to CSV (--airspeed-kt A:B:S | --hover-wod-kt A:B:S, --wod-dir-deg, --trim-constraint, --csv, --modes, --field F.h5 --cg-S X,Y,Z)"},
#endif
    {"render", cmd_render, "render SCENARIO -o PNG    off-screen deck view (--eye-S, --target-S, --size, --fov-deg)"},
#ifdef DISIM_HAVE_CFD
    {"airwake", cmd_airwake, "airwake SCENARIO -o F.h5   steady RANS airwake (--wod-speed-kt, --wod-dir-deg, --rotor, --grid)"},
    {"probe", cmd_probe, "probe FIELD.h5 --line ...  CSV velocities along X0,Y0,Z0:X1,Y1,Z1:N (frame S)"},
    {"validate", cmd_validate, "validate CASE             CFD validation case (cavity100 cavity1000 bfs disk-oge disk-ige sfs2 sfs2-grid)"},
#endif
#ifdef DISIM_HAVE_AIRWAKED
    {"airwaked", cmd_airwaked, "airwaked DB_DIR           background airwake builder (--jobs N, --ships DIR, --exit-when-idle, --no-lcm)"},
#endif
#ifdef DISIM_HAVE_SHOL_CMD
    {"fly", cmd_fly, "fly SCENARIO              the flight loop: a trimmed hover in the airwake (--fast, --duration, --rate-hz, --csv)"},
    {"shol", cmd_shol, "shol SCENARIO             candidate SHOL envelope (--grid, --coupling, -o DIR, --db DIR, --full-circle)"},
#endif
    {"ios", cmd_ios, "ios                       instructor's console of disim fly: freeze, reset, reposition, WOD, sea, turbulence, snapshots (--cmd, --script, --lcm)"},
    {"station", cmd_station, "station                   pilot station: keyboard, evdev joystick or --script CSV on LCM (--device, --list, --id, --lcm)"},
};

static int cmd_help(int argc, char **argv)
{
    (void)argc;
    (void)argv;
    printf("disim -- ship-helicopter dynamic interface simulator\n\nusage: disim COMMAND [ARGS]\n\n");
    for (size_t i = 0; i < sizeof cmds / sizeof cmds[0]; i++)
        printf("  disim %s\n", cmds[i].usage);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        cmd_help(0, NULL);
        return 2;
    }
    /* The background builder shares the machine (with a shol run, a flight
     * loop, another builder): its OpenMP threads must not spin at barriers
     * while a team mate waits for a core. libgomp's default spins about
     * 300,000 times; beside another 2-thread builder on 2 cores, shol_e2e
     * took 307 s instead of 20 s (docs/benchmarks.md, "OpenMP threads side
     * by side").
     * 1000 spins cost one process alone nothing measurable. libgomp reads
     * the variable when it loads, so the builder re-executes itself once
     * with it set, unless the user chose a wait policy. */
    if (!strcmp(argv[1], "airwaked") && !getenv("GOMP_SPINCOUNT") && !getenv("OMP_WAIT_POLICY") &&
        setenv("GOMP_SPINCOUNT", "1000", 1) == 0)
        execv("/proc/self/exe", argv); /* on failure: go on with the default */
    for (size_t i = 0; i < sizeof cmds / sizeof cmds[0]; i++)
        if (strcmp(argv[1], cmds[i].name) == 0)
            return cmds[i].fn(argc - 1, argv + 1);
    if (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h"))
        return cmd_help(0, NULL);
    fprintf(stderr, "disim: unknown command '%s' (try 'disim help')\n", argv[1]);
    return 2;
}

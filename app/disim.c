/* disim.c -- the disim command: a thin dispatcher over the libraries. Each
 * subcommand parses its flags, calls one library entry point and maps its
 * return code to the exit status (0 ok, 1 bad input or failure). */
#include "cmds.h"
#include "core.h"
#include "sim.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef int (*cmd_fn)(int argc, char **argv);

static int cmd_help(int argc, char **argv);

static int cmd_check(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: disim check SCENARIO.ini\n");
        return 2;
    }
    sim_scenario *sc = malloc(sizeof *sc);
    if (!sc)
        return 1;
    core_err err = {{0}};
    int rc = sim_scenario_load(argv[1], sc, &err);
    if (rc) {
        fprintf(stderr, "disim check: %s\n", err.msg);
        free(sc);
        return 1;
    }
    sim_scenario_print(sc, stdout);
    free(sc);
    return 0;
}

static const struct {
    const char *name;
    cmd_fn fn;
    const char *usage;
} cmds[] = {
    {"help", cmd_help, "help                      this text"},
    {"check", cmd_check, "check SCENARIO            parse and resolve a scenario, print it"},
    {"render", cmd_render, "render SCENARIO -o PNG    off-screen deck view (--eye-S, --target-S, --size, --fov-deg)"},
#ifdef DISIM_HAVE_AIRWAKED
    {"airwaked", cmd_airwaked, "airwaked DB_DIR           background airwake builder (--jobs N, --ships DIR, --exit-when-idle, --no-lcm)"},
#endif
#ifdef DISIM_HAVE_SHOL
    {"shol", cmd_shol, "shol SCENARIO             candidate SHOL envelope (--grid, --coupling, -o DIR, --db DIR, --full-circle)"},
#endif
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
    for (size_t i = 0; i < sizeof cmds / sizeof cmds[0]; i++)
        if (strcmp(argv[1], cmds[i].name) == 0)
            return cmds[i].fn(argc - 1, argv + 1);
    if (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h"))
        return cmd_help(0, NULL);
    fprintf(stderr, "disim: unknown command '%s' (try 'disim help')\n", argv[1]);
    return 2;
}

/* case.c -- the named options of an airwake case (grid level, rotor mode,
 * coupling mode), shared by the scenario reader, the command line, the
 * airwake database's keys, the CFD solver and the coupling, so that each
 * has one type and one spelling everywhere. The choice strings for the
 * INI reader are the same names joined by '|' (test_core checks that
 * they agree). */
#include "core.h"

#include <string.h>

static const char *const grid_names[CORE_GRID_NLEVELS + 1] = {"coarse", "default", "fine", "quick"};
static const char *const rotor_names[CORE_ROTOR_NMODES] = {"off", "uniform", "loaded"};
static const char *const coupling_names[CORE_COUPLING_NMODES] = {"two-way", "one-way"};

static const char *name_of(const char *const *names, int n, int v)
{
    return v >= 0 && v < n ? names[v] : "?";
}

static int parse_of(const char *const *names, int n, const char *s)
{
    for (int v = 0; s && v < n; v++)
        if (!strcmp(s, names[v]))
            return v;
    return -1;
}

const char *core_grid_name(int level) { return name_of(grid_names, CORE_GRID_NLEVELS + 1, level); }
int core_grid_parse(const char *s) { return parse_of(grid_names, CORE_GRID_NLEVELS, s); }
int core_grid_parse_any(const char *s) { return parse_of(grid_names, CORE_GRID_NLEVELS + 1, s); }
int core_grid_rank(int level)
{
    static const int rank[CORE_GRID_NLEVELS + 1] = {1, 2, 3, 0};
    return level >= 0 && level <= CORE_GRID_QUICK ? rank[level] : -1;
}
const char *core_grid_choices(void) { return "coarse|default|fine"; }

const char *core_rotor_name(int mode) { return name_of(rotor_names, CORE_ROTOR_NMODES, mode); }
int core_rotor_parse(const char *s) { return parse_of(rotor_names, CORE_ROTOR_NMODES, s); }
const char *core_rotor_choices(void) { return "off|uniform|loaded"; }

const char *core_coupling_name(int mode) { return name_of(coupling_names, CORE_COUPLING_NMODES, mode); }
int core_coupling_parse(const char *s) { return parse_of(coupling_names, CORE_COUPLING_NMODES, s); }
const char *core_coupling_choices(void) { return "two-way|one-way"; }

/* grid.c -- the names of the airwake grid levels, shared by the scenario
 * reader, the command line, the airwake database's keys and the CFD
 * validation, so that a level has one spelling everywhere. */
#include "core.h"

#include <string.h>

static const char *const names[CORE_GRID_NLEVELS] = {"coarse", "default", "fine"};

const char *core_grid_name(int level)
{
    return level >= 0 && level < CORE_GRID_NLEVELS ? names[level] : "?";
}

int core_grid_parse(const char *s)
{
    for (int l = 0; s && l < CORE_GRID_NLEVELS; l++)
        if (!strcmp(s, names[l]))
            return l;
    return -1;
}

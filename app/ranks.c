/* ranks.c -- a process's rank in a sweep spread over several processes,
 * from its launcher's environment (no MPI library: the launchers say the
 * rank and the count in variables; see cmds.h and docs/cluster.md). */
#include "cmds.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A variable's whole number in [lo, hi]: 1 set and valid, 0 unset, -1 bad. */
static int env_int(const char *name, int lo, int hi, int *out)
{
    const char *s = getenv(name);
    if (!s || !*s)
        return 0;
    char *end;
    long v = strtol(s, &end, 10);
    if (*end || v < lo || v > hi) {
        fprintf(stderr, "disim: %s='%s': expected a whole number from %d to %d\n", name, s, lo, hi);
        return -1;
    }
    *out = (int)v;
    return 1;
}

static void keep_safe(char *s)
{
    for (char *p = s; *p; p++)
        if (!((*p >= 'a' && *p <= 'z') || (*p >= 'A' && *p <= 'Z') || (*p >= '0' && *p <= '9') || *p == '.' ||
              *p == '_' || *p == '-'))
            *p = '_';
}

int app_ranks_from_env(int *rank, int *ranks, char *run_id, size_t n)
{
    static const char *const vars[][2] = {{"OMPI_COMM_WORLD_RANK", "OMPI_COMM_WORLD_SIZE"},
                                          {"PMI_RANK", "PMI_SIZE"},
                                          {"SLURM_PROCID", "SLURM_STEP_NUM_TASKS"}};
    *rank = 0;
    *ranks = 1;
    run_id[0] = '\0';
    for (size_t k = 0; k < sizeof vars / sizeof vars[0]; k++) {
        int r = 0, nr = 0;
        int a = env_int(vars[k][1], 1, 1 << 20, &nr);
        if (a < 0)
            return -1;
        if (a == 0)
            continue;
        int b = env_int(vars[k][0], 0, nr - 1, &r);
        if (b < 0)
            return -1;
        if (b == 0)
            continue;
        *rank = r;
        *ranks = nr;
        break;
    }
    const char *ns = getenv("PMIX_NAMESPACE"), *job = getenv("SLURM_JOB_ID"), *step = getenv("SLURM_STEP_ID");
    if (ns && *ns)
        snprintf(run_id, n, "%s", ns);
    else if (job && *job)
        snprintf(run_id, n, "slurm-%s.%s", job, step && *step ? step : "0");
    keep_safe(run_id);
    return 0;
}

/* task.c -- the task file: what the automated pilot flies (sim_task),
 * read from an INI file (scenarios/README.md, "Task files", has the
 * keys; sim/pilot_auto.c flies it).
 *
 * A phase file: [task] type (station_keep or land), phases = NAME, ...
 * (1 to SIM_TASK_MAX_PHASES names of letters, digits, _ or -, each once),
 * heading_deg (the phases' default, 0); and a [phase NAME] section for
 * each: kind (hold, move, descend), at (spot, port_edge, starboard_edge,
 * aft_edge: a deck anchor from the ship file, the edges needing the ship,
 * sim_task_load_ship), offset_m (x, y from it in S), heading_deg, height_m
 * (not descend), duration_s (hold), speed_mps (move), descent_mps,
 * quiescent, quiet_energy, quiet_window_s, max_wait_s (descend), and the
 * desired_* and adequate_* bands (pos_m, height_m (not descend),
 * heading_deg, time_s; descend: sink_mps, drift_mps), adequate no tighter
 * than desired. A hold phase first (the start: start_S_m), a descend
 * phase only last and only in a land task, which must have one. The
 * legacy fields of sim_task are the last hold phase's (the hover before
 * the descent).
 *
 * The one-point form: [task] type, target_S_m (x, y, z in S, z < 0),
 * heading_deg, duration_s, land: touchdown_height_m (below the hover's
 * height), descent_mps; [desired] and [adequate] (pos_m, height_m,
 * heading_deg, time_s, land: sink_mps). It is one hold phase, and for
 * land a descend phase after it (no time asked).
 *
 * A key not read, or a [phase NAME] section not in the list, is an error
 * naming the file and line.
 */
#include "sim.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>


static double phase_length_s(const sim_task_phase *ph, double from_z)
{
    switch (ph->kind) {
    case SIM_PHASE_HOLD:
        return ph->adequate.time_s + ph->duration_s;
    case SIM_PHASE_MOVE:
        return ph->adequate.time_s;
    default: /* the wait, the descent, and as long again with 10 s to settle */
        return (ph->quiescent ? ph->max_wait_s : 0.0) + 2.0 * fmax(-from_z, 0.0) / ph->descent_mps + 10.0;
    }
}

double sim_task_length_s(const sim_task *t)
{
    double T = 0.0, z = t->nphases ? t->phase[0].target_S_m[2] : 0.0;
    for (int i = 0; i < t->nphases; i++) {
        T += phase_length_s(&t->phase[i], z);
        if (t->phase[i].kind != SIM_PHASE_DESCEND)
            z = t->phase[i].target_S_m[2];
    }
    return T;
}

/* The tolerances of a legacy section ([desired], [adequate]). */
static int tol_section(core_ini *ini, const char *s, int land, sim_task_tol *tol, core_err *err)
{
    double hd;
    int rc;
    if ((land && (rc = core_ini_get_double(ini, s, "sink_mps", 1, 0.01, 20.0, &tol->sink_mps, err))) ||
        (rc = core_ini_get_double(ini, s, "pos_m", 1, 0.01, 100.0, &tol->pos_m, err)) ||
        (rc = core_ini_get_double(ini, s, "height_m", 1, 0.01, 100.0, &tol->height_m, err)) ||
        (rc = core_ini_get_double(ini, s, "heading_deg", 1, 0.01, 180.0, &hd, err)) ||
        (rc = core_ini_get_double(ini, s, "time_s", 1, 0.0, 3600.0, &tol->time_s, err)))
        return rc < 0 ? rc : -1;
    tol->heading_rad = hd * CORE_DEG_TO_RAD;
    return 0;
}

static int tol_tighter(const sim_task_tol *a, const sim_task_tol *d)
{
    return a->pos_m < d->pos_m || a->height_m < d->height_m || a->heading_rad < d->heading_rad ||
           a->time_s < d->time_s || a->sink_mps < d->sink_mps || a->drift_mps < d->drift_mps;
}

/* A phase's band: KIND_pos_m, KIND_height_m (not descend), KIND_heading_deg,
 * KIND_time_s, descend: KIND_sink_mps, KIND_drift_mps. */
static int phase_tol(core_ini *ini, const char *sec, const char *band, int kind, sim_task_tol *tol, core_err *err)
{
    char k[6][48];
    const char *names[6] = {"pos_m", "height_m", "heading_deg", "time_s", "sink_mps", "drift_mps"};
    for (int i = 0; i < 6; i++)
        snprintf(k[i], sizeof k[i], "%s_%s", band, names[i]);
    double hd;
    int rc, d = kind == SIM_PHASE_DESCEND;
    if ((rc = core_ini_get_double(ini, sec, k[0], 1, 0.01, 100.0, &tol->pos_m, err)) ||
        (!d && (rc = core_ini_get_double(ini, sec, k[1], 1, 0.01, 100.0, &tol->height_m, err))) ||
        (rc = core_ini_get_double(ini, sec, k[2], 1, 0.01, 180.0, &hd, err)) ||
        (rc = core_ini_get_double(ini, sec, k[3], 1, 0.0, 3600.0, &tol->time_s, err)) ||
        (d && (rc = core_ini_get_double(ini, sec, k[4], 1, 0.01, 20.0, &tol->sink_mps, err))) ||
        (d && (rc = core_ini_get_double(ini, sec, k[5], 1, 0.01, 20.0, &tol->drift_mps, err))))
        return rc < 0 ? rc : -1;
    tol->heading_rad = hd * CORE_DEG_TO_RAD;
    if (d)
        tol->height_m = 100.0;
    return 0;
}

/* The deck's anchors in S (the ship file's flight deck): x, y. */
static int anchor(const core_ship *ship, int which, double xy[2])
{
    xy[0] = xy[1] = 0.0;
    if (which == 0)
        return 0;
    if (!ship)
        return -1;
    if (which == 1)
        xy[1] = -ship->deck_halfwidth_m;
    else if (which == 2)
        xy[1] = ship->deck_halfwidth_m;
    else
        xy[0] = ship->deck_x0_m;
    return 0;
}

static int load_phase(core_ini *ini, const char *path, const char *name, const core_ship *ship, double hd_task,
                      sim_task_phase *ph, core_err *err)
{
    char sec[64];
    snprintf(sec, sizeof sec, "phase %s", name);
    memset(ph, 0, sizeof *ph);
    snprintf(ph->name, sizeof ph->name, "%s", name);
    if (!core_ini_has_section(ini, sec))
        return core_err_set(err, -1, "%s: [task] phases: no section [%s]", path, sec);
    int rc, at = 0, n = 0;
    double off[2] = {0.0, 0.0}, h = 0.0, hd = 0.0;
    if ((rc = core_ini_get_enum(ini, sec, "kind", 1, "hold|move|descend", &ph->kind, err)) ||
        (rc = core_ini_get_enum(ini, sec, "at", 1, "spot|port_edge|starboard_edge|aft_edge", &at, err)))
        return rc < 0 ? rc : -1;
    if ((rc = core_ini_get_doubles(ini, sec, "offset_m", 0, -500.0, 500.0, off, 2, &n, err)) < 0)
        return rc;
    if (rc == 0 && n != 2)
        return core_err_set(err, -1, "%s:%d: [%s] offset_m: expected two numbers x,y (m, S)", path,
                            core_ini_find(ini, sec, "offset_m")->line, sec);
    double xy[2];
    if (anchor(ship, at, xy) != 0)
        return core_err_set(err, -1, "%s:%d: [%s] at: a deck edge needs the ship (sim_task_load_ship)", path,
                            core_ini_find(ini, sec, "at")->line, sec);
    if ((rc = core_ini_get_double(ini, sec, "heading_deg", 0, -180.0, 180.0, &hd, err)) < 0)
        return rc;
    ph->heading_rad = rc == 0 ? hd * CORE_DEG_TO_RAD : hd_task; /* absent: the task's */
    if (ph->kind != SIM_PHASE_DESCEND && (rc = core_ini_get_double(ini, sec, "height_m", 1, 0.5, 100.0, &h, err)))
        return rc < 0 ? rc : -1;
    ph->target_S_m[0] = xy[0] + off[0];
    ph->target_S_m[1] = xy[1] + off[1];
    ph->target_S_m[2] = -h;
    if (ph->kind == SIM_PHASE_HOLD &&
        (rc = core_ini_get_double(ini, sec, "duration_s", 1, 0.0, 3600.0, &ph->duration_s, err)))
        return rc < 0 ? rc : -1;
    if (ph->kind == SIM_PHASE_MOVE &&
        (rc = core_ini_get_double(ini, sec, "speed_mps", 1, 0.05, 10.0, &ph->speed_mps, err)))
        return rc < 0 ? rc : -1;
    if (ph->kind == SIM_PHASE_DESCEND) {
        ph->quiet_energy = 0.25;
        ph->quiet_window_s = 1.0;
        ph->max_wait_s = 60.0;
        if ((rc = core_ini_get_double(ini, sec, "descent_mps", 1, 0.05, 5.0, &ph->descent_mps, err)) ||
            (rc = core_ini_get_bool(ini, sec, "quiescent", 1, &ph->quiescent, err)))
            return rc < 0 ? rc : -1;
        if ((rc = core_ini_get_double(ini, sec, "quiet_energy", 0, 0.01, 10.0, &ph->quiet_energy, err)) < 0 ||
            (rc = core_ini_get_double(ini, sec, "quiet_window_s", 0, 0.0, 60.0, &ph->quiet_window_s, err)) < 0 ||
            (rc = core_ini_get_double(ini, sec, "max_wait_s", 0, 0.0, 3600.0, &ph->max_wait_s, err)) < 0)
            return rc;
    }
    if ((rc = phase_tol(ini, sec, "desired", ph->kind, &ph->desired, err)) ||
        (rc = phase_tol(ini, sec, "adequate", ph->kind, &ph->adequate, err)))
        return rc;
    if (tol_tighter(&ph->adequate, &ph->desired))
        return core_err_set(err, -1, "%s: [%s]: expected each adequate tolerance and time no tighter than desired's",
                            path, sec);
    return 0;
}

/* A phase file: [task] type, phases = a, b, ...; [phase NAME] each. */
static int load_phases(core_ini *ini, const char *path, const core_ship *ship, int kind, sim_task *t, core_err *err)
{
    char list[512];
    int rc;
    double hd = 0.0;
    if ((rc = core_ini_get_string(ini, "task", "phases", 1, list, sizeof list, err)) ||
        (rc = core_ini_get_double(ini, "task", "heading_deg", 0, -180.0, 180.0, &hd, err)) < 0)
        return rc < 0 ? rc : -1;
    int line = core_ini_find(ini, "task", "phases")->line;
    char *save = NULL;
    for (char *tok = strtok_r(list, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
        while (*tok == ' ' || *tok == '\t')
            tok++;
        size_t L = strlen(tok);
        while (L && (tok[L - 1] == ' ' || tok[L - 1] == '\t'))
            tok[--L] = '\0';
        int bad = !L || L >= sizeof t->phase[0].name || t->nphases == SIM_TASK_MAX_PHASES;
        for (size_t k = 0; k < L; k++)
            bad |= !(isalnum((unsigned char)tok[k]) || tok[k] == '_' || tok[k] == '-');
        if (bad)
            return core_err_set(err, -1,
                                "%s:%d: [task] phases: expected 1 to %d names of up to %d letters, digits, _ or -",
                                path, line, SIM_TASK_MAX_PHASES, (int)sizeof t->phase[0].name - 1);
        for (int i = 0; i < t->nphases; i++)
            if (!strcmp(t->phase[i].name, tok))
                return core_err_set(err, -1, "%s:%d: [task] phases: '%s' twice", path, line, tok);
        if ((rc = load_phase(ini, path, tok, ship, hd * CORE_DEG_TO_RAD, &t->phase[t->nphases], err)))
            return rc;
        t->nphases++;
    }
    if (!t->nphases || t->phase[0].kind != SIM_PHASE_HOLD)
        return core_err_set(err, -1, "%s:%d: [task] phases: expected a hold phase first (the start)", path, line);
    int last_hold = -1, ndesc = 0;
    for (int i = 0; i < t->nphases; i++) {
        if (t->phase[i].kind == SIM_PHASE_HOLD)
            last_hold = i;
        if (t->phase[i].kind == SIM_PHASE_DESCEND && (++ndesc > 1 || i != t->nphases - 1))
            return core_err_set(err, -1, "%s:%d: [task] phases: a descend phase only last", path, line);
    }
    if ((kind == SIM_TASK_LAND) != (ndesc == 1))
        return core_err_set(err, -1, "%s:%d: [task] phases: type %s: expected %s", path, line,
                            kind == SIM_TASK_LAND ? "land" : "station_keep",
                            kind == SIM_TASK_LAND ? "a descend phase last" : "no descend phase");
    /* the legacy fields: the last hold phase's (the hover before a descent) */
    const sim_task_phase *h = &t->phase[last_hold];
    memcpy(t->target_S_m, h->target_S_m, sizeof t->target_S_m);
    t->heading_rad = h->heading_rad;
    t->duration_s = h->duration_s;
    t->desired = h->desired;
    t->adequate = h->adequate;
    if (ndesc) {
        t->descent_mps = t->phase[t->nphases - 1].descent_mps;
        t->desired.sink_mps = t->phase[t->nphases - 1].desired.sink_mps;
        t->adequate.sink_mps = t->phase[t->nphases - 1].adequate.sink_mps;
    }
    t->has_start = 1;
    memcpy(t->start_S_m, t->phase[0].target_S_m, sizeof t->start_S_m);
    return 0;
}

void sim_task_legacy_phases(sim_task *t)
{
    sim_task_phase *h = &t->phase[0];
    snprintf(h->name, sizeof h->name, "hover");
    h->kind = SIM_PHASE_HOLD;
    memcpy(h->target_S_m, t->target_S_m, sizeof h->target_S_m);
    h->heading_rad = t->heading_rad;
    h->duration_s = t->duration_s;
    h->desired = t->desired;
    h->adequate = t->adequate;
    t->nphases = 1;
    if (t->kind == SIM_TASK_LAND) {
        sim_task_phase *d = &t->phase[1];
        *d = *h;
        snprintf(d->name, sizeof d->name, "descent");
        d->kind = SIM_PHASE_DESCEND;
        d->duration_s = 0.0;
        d->descent_mps = t->descent_mps;
        d->desired.time_s = d->adequate.time_s = 3600.0; /* no time asked */
        d->desired.height_m = d->adequate.height_m = 100.0;
        t->nphases = 2;
    }
}

/* A legacy file: target_S_m, [desired], [adequate]. */
static int load_legacy(core_ini *ini, const char *path, int kind, sim_task *t, core_err *err)
{
    int n = 0, rc;
    double hd = 0.0;
    if ((rc = core_ini_get_doubles(ini, "task", "target_S_m", 1, -500.0, 500.0, t->target_S_m, 3, &n, err)))
        return rc < 0 ? rc : -1;
    if (n != 3)
        return core_err_set(err, -1, "%s:%d: [task] target_S_m: expected three numbers x,y,z (m, S)", path,
                            core_ini_find(ini, "task", "target_S_m")->line);
    if (!(t->target_S_m[2] < 0.0))
        return core_err_set(err, -1, "%s:%d: [task] target_S_m: expected z < 0 (above the deck; S is z down)", path,
                            core_ini_find(ini, "task", "target_S_m")->line);
    if ((rc = core_ini_get_double(ini, "task", "heading_deg", 0, -180.0, 180.0, &hd, err)) < 0 ||
        (rc = core_ini_get_double(ini, "task", "duration_s", 1, 0.1, 3600.0, &t->duration_s, err)) ||
        (rc = tol_section(ini, "desired", kind == SIM_TASK_LAND, &t->desired, err)) ||
        (rc = tol_section(ini, "adequate", kind == SIM_TASK_LAND, &t->adequate, err)))
        return rc < 0 ? rc : -1;
    if (kind == SIM_TASK_LAND) {
        if ((rc = core_ini_get_double(ini, "task", "touchdown_height_m", 1, 0.1, 20.0, &t->touchdown_height_m, err)) ||
            (rc = core_ini_get_double(ini, "task", "descent_mps", 1, 0.05, 5.0, &t->descent_mps, err)))
            return rc < 0 ? rc : -1;
        if (!(-t->target_S_m[2] > t->touchdown_height_m))
            return core_err_set(err, -1, "%s:%d: [task] touchdown_height_m: expected below the hover's height (%.2f m)",
                                path, core_ini_find(ini, "task", "touchdown_height_m")->line, -t->target_S_m[2]);
    }
    t->heading_rad = hd * CORE_DEG_TO_RAD;
    t->kind = kind;
    if (tol_tighter(&t->adequate, &t->desired))
        return core_err_set(err, -1, "%s: [adequate]: expected each tolerance and time no tighter than [desired]'s",
                            path);
    sim_task_legacy_phases(t);
    return 0;
}

int sim_task_load_ship(const char *path, const core_ship *ship, sim_task *t, core_err *err)
{
    memset(t, 0, sizeof *t);
    core_ini *ini = core_ini_load(path, err);
    if (!ini)
        return -1;
    int rc = sim_task_from_ini(ini, ship, t, err);
    core_ini_destroy(ini);
    return rc;
}

int sim_task_from_ini(core_ini *ini, const core_ship *ship, sim_task *t, core_err *err)
{
    memset(t, 0, sizeof *t);
    const char *path = core_ini_path(ini);
    int kind = 0, rc;
    if ((rc = core_ini_get_enum(ini, "task", "type", 1, "station_keep|land", &kind, err)) == 0) {
        rc = core_ini_find(ini, "task", "phases") ? load_phases(ini, path, ship, kind, t, err)
                                                  : load_legacy(ini, path, kind, t, err);
        t->kind = kind;
    }
    if (rc == 0) {
        /* a legacy file's sections, or a phase file's, not both */
        for (size_t i = 0; i < core_ini_count(ini) && rc == 0; i++) {
            const core_ini_entry *e = core_ini_at(ini, i);
            if (!e->used && !strncmp(e->section, "phase ", 6))
                rc = core_err_set(err, -1, "%s:%d: [%s]: not in [task] phases", path, e->line, e->section);
        }
        if (rc == 0)
            rc = core_ini_check_unused(ini, err);
    }
    if (rc)
        memset(t, 0, sizeof *t);
    return rc < 0 ? rc : (rc ? -1 : 0);
}

int sim_task_load(const char *path, sim_task *t, core_err *err) { return sim_task_load_ship(path, NULL, t, err); }

int sim_task_start_S(const char *path, const core_ship *ship, double start_S_m[3], core_err *err)
{
    sim_task *t = malloc(sizeof *t);
    if (!t)
        return core_err_set(err, -1, "pilot_auto: out of memory");
    int rc = sim_task_load_ship(path, ship, t, err);
    if (rc == 0 && t->has_start)
        memcpy(start_S_m, t->start_S_m, 3 * sizeof *start_S_m);
    free(t);
    return rc;
}

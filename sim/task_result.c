/* task_result.c -- the automated pilot's task result (sim_task_result)
 * written per run as CSV (a header line and one row, so that many runs'
 * files concatenate into one table) and as JSON (the same figures, the
 * phases as an array), each to PATH.tmpPID and renamed into place: a
 * reader sees a whole file or none. Angles in degrees, the rest SI as the
 * column names say; a figure not had (no touchdown) is empty in the CSV
 * and null in the JSON.
 */
#include "sim.h"

#include <math.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>


static const char *grade_name(int g) { return g == 2 ? "desired" : g == 1 ? "adequate" : g == 0 ? "not_met" : ""; }
static const char *kind_name(int k) { return k == SIM_PHASE_HOLD ? "hold" : k == SIM_PHASE_MOVE ? "move" : "descend"; }
static const char *const ctl[4] = {"collective", "long", "lat", "pedal"};

/* One number: %.6g, or empty (CSV) / null (JSON) when not finite. */
static void num(FILE *f, double v, int json)
{
    if (isfinite(v))
        fprintf(f, "%.6g", v);
    else if (json)
        fputs("null", f);
}

typedef struct col {
    const char *name;
    double v;
} col;

/* The run's scalar figures, in the order of the CSV's columns. */
static int scalars(const sim_task_result *r, col *c)
{
    int n = 0, td = r->touched;
    double nan = NAN;
    c[n++] = (col){"t_end_s", r->t_s};
    c[n++] = (col){"t_descent_s", r->t_descent_s >= 0.0 ? r->t_descent_s : nan};
    c[n++] = (col){"t_touchdown_s", td ? r->t_touchdown_s : nan};
    c[n++] = (col){"sink_mps", td ? r->sink_mps : nan};
    c[n++] = (col){"drift_mps", td ? r->drift_mps : nan};
    c[n++] = (col){"dist_spot_m", td ? r->dist_m : nan};
    c[n++] = (col){"heading_err_deg", td ? r->td_heading_err_rad * CORE_RAD_TO_DEG : nan};
    c[n++] = (col){"roll_deck_deg", td ? r->td_roll_deck_rad * CORE_RAD_TO_DEG : nan};
    c[n++] = (col){"pitch_deck_deg", td ? r->td_pitch_deck_rad * CORE_RAD_TO_DEG : nan};
    c[n++] = (col){"heave_m", td ? r->td_heave_m : nan};
    c[n++] = (col){"heave_rate_mps", td ? r->td_heave_rate_mps : nan};
    c[n++] = (col){"heave_phase_deg", td ? r->td_heave_phase_rad * CORE_RAD_TO_DEG : nan};
    c[n++] = (col){"heave_energy", td ? r->td_energy : nan};
    c[n++] = (col){"t_settled_s", r->settled ? r->t_settled_s : nan};
    c[n++] = (col){"stop_steps", (double)r->stop_steps};
    return n;
}

/* Control i's activity (its suffixes after the control's name). */
static void ctl_cols(const sim_task_result *r, int i, col c[3])
{
    c[0] = (col){"rms_pct", r->ctl_rms_pct[i]};
    c[1] = (col){"rate_rms_pctps", r->ctl_rate_rms_pctps[i]};
    c[2] = (col){"cutoff_radps", r->ctl_cutoff_radps[i]};
}

/* Phase i's figures after its grade (suffixes after the phase's name). */
static void phase_cols(const sim_task *t, const sim_task_result *r, int i, col c[6])
{
    const sim_phase_result *p = &r->phase[i];
    int flown = p->grade >= 0, desc = t->phase[i].kind == SIM_PHASE_DESCEND;
    c[0] = (col){"t_start_s", p->t_start_s >= 0.0 ? p->t_start_s : NAN};
    c[1] = (col){"t_end_s", p->t_end_s >= 0.0 ? p->t_end_s : NAN};
    c[2] = (col){"max_err_pos_m", flown ? p->max_err_pos_m : NAN};
    c[3] = (col){"max_err_height_m", flown && !desc ? p->max_err_height_m : NAN};
    c[4] = (col){"max_err_heading_deg", flown ? p->max_err_heading_rad * CORE_RAD_TO_DEG : NAN};
    c[5] = (col){"wait_s", flown && desc ? p->t_wait_s : NAN};
}

static const char *phase_grade(const sim_task_result *r, int i)
{
    return r->phase[i].grade >= 0 ? grade_name(r->phase[i].grade) : "not_flown";
}

static int write_csv(FILE *f, const sim_task *t, const sim_task_result *r)
{
    col c[32];
    int n = scalars(r, c);
    fputs("task_grade,touched,touchdown_grade,settled", f);
    for (int i = 0; i < n; i++)
        fprintf(f, ",%s", c[i].name);
    col a[6];
    for (int i = 0; i < 4; i++) {
        ctl_cols(r, i, a);
        for (int k = 0; k < 3; k++)
            fprintf(f, ",%s_%s", ctl[i], a[k].name);
    }
    for (int i = 0; i < t->nphases; i++) {
        phase_cols(t, r, i, a);
        fprintf(f, ",%s_grade", t->phase[i].name);
        for (int k = 0; k < 6; k++)
            fprintf(f, ",%s_%s", t->phase[i].name, a[k].name);
    }
    fprintf(f, "\n%s,%d,%s,%d", grade_name(r->grade), r->touched, r->touched ? grade_name(r->touchdown_grade) : "",
            r->settled);
    for (int i = 0; i < n; i++) {
        fputc(',', f);
        num(f, c[i].v, 0);
    }
    for (int i = 0; i < 4; i++) {
        ctl_cols(r, i, a);
        for (int k = 0; k < 3; k++) {
            fputc(',', f);
            num(f, a[k].v, 0);
        }
    }
    for (int i = 0; i < t->nphases; i++) {
        phase_cols(t, r, i, a);
        fprintf(f, ",%s", phase_grade(r, i));
        for (int k = 0; k < 6; k++) {
            fputc(',', f);
            num(f, a[k].v, 0);
        }
    }
    fputc('\n', f);
    return 0;
}

static int write_json(FILE *f, const sim_task *t, const sim_task_result *r)
{
    col c[32];
    int n = scalars(r, c);
    fprintf(f, "{\n  \"task_grade\": \"%s\",\n  \"touched\": %s,\n  \"touchdown_grade\": ", grade_name(r->grade),
            r->touched ? "true" : "false");
    if (r->touched)
        fprintf(f, "\"%s\"", grade_name(r->touchdown_grade));
    else
        fputs("null", f);
    fprintf(f, ",\n  \"settled\": %s", r->settled ? "true" : "false");
    for (int i = 0; i < n; i++) {
        fprintf(f, ",\n  \"%s\": ", c[i].name);
        num(f, c[i].v, 1);
    }
    fputs(",\n  \"control_activity\": {", f);
    col a[6];
    for (int i = 0; i < 4; i++) {
        ctl_cols(r, i, a);
        fprintf(f, "%s\n    \"%s\": {", i ? "," : "", ctl[i]);
        for (int k = 0; k < 3; k++) {
            fprintf(f, "%s\"%s\": ", k ? ", " : "", a[k].name);
            num(f, a[k].v, 1);
        }
        fputc('}', f);
    }
    fputs("\n  },\n  \"phases\": [", f);
    for (int i = 0; i < t->nphases; i++) {
        phase_cols(t, r, i, a);
        fprintf(f, "%s\n    {\"name\": \"%s\", \"kind\": \"%s\", \"grade\": \"%s\"", i ? "," : "",
                t->phase[i].name, kind_name(t->phase[i].kind), phase_grade(r, i));
        for (int k = 0; k < 6; k++) {
            fprintf(f, ", \"%s\": ", a[k].name);
            num(f, a[k].v, 1);
        }
        fputc('}', f);
    }
    fputs("\n  ]\n}\n", f);
    return 0;
}

/* Write through PATH.tmpPID, flushed, synced and renamed. */
static int write_atomic(const char *path, int json, const sim_task *t, const sim_task_result *r, core_err *err)
{
    if (!path)
        return 0;
    char tmp[SIM_PATH_MAX + 32];
    snprintf(tmp, sizeof tmp, "%s.tmp%ld", path, (long)getpid());
    FILE *f = fopen(tmp, "w");
    if (!f)
        return core_err_set(err, -1, "%s: cannot write the task result", tmp);
    if (json)
        write_json(f, t, r);
    else
        write_csv(f, t, r);
    int bad = ferror(f) || fflush(f) != 0 || fsync(fileno(f)) != 0;
    bad |= fclose(f) != 0;
    if (bad || rename(tmp, path) != 0) {
        unlink(tmp);
        return core_err_set(err, -1, "%s: cannot write the task result (nothing written)", path);
    }
    return 0;
}

int sim_task_result_write(const sim_task *t, const sim_task_result *r, const char *csv_path, const char *json_path,
                          core_err *err)
{
    if (!t || !r || t->nphases < 1 || t->nphases > SIM_TASK_MAX_PHASES)
        return core_err_set(err, -1, "task result: expected a task with 1 to %d phases and its result",
                            SIM_TASK_MAX_PHASES);
    if ((csv_path && strlen(csv_path) >= SIM_PATH_MAX) || (json_path && strlen(json_path) >= SIM_PATH_MAX))
        return core_err_set(err, -1, "task result: a path longer than %d characters", SIM_PATH_MAX - 1);
    if (write_atomic(csv_path, 0, t, r, err) != 0)
        return -1;
    if (write_atomic(json_path, 1, t, r, err) != 0) {
        if (csv_path)
            unlink(csv_path); /* the pair or nothing */
        return -1;
    }
    return 0;
}

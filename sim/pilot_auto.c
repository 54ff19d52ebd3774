/* pilot_auto.c -- the automated pilot: a multi-loop human pilot model that
 * flies a task file with the four controls a person has.
 *
 * The model. Each inner loop is closed as the crossover model of McRuer
 * and Krendel (1974, AGARDograph AG-188, the crossover model of their
 * chapter on compensatory tracking): near crossover the pilot adapts so
 * that pilot and aircraft together look like
 *     Y_p Y_c = w_c exp(-tau s) / s,
 * an integrator at the crossover frequency w_c behind the pilot's pure
 * delay tau. Around hover each axis of the bare airframe is, to first
 * order, an attitude (or height) behind a first-order rate response,
 *     Y_c = K / (s (s - a)),
 * (roll: K = L_lat, a = L_p; pitch: M_long, M_q; heading: N_ped, N_r;
 * height, z down: Z_col, Z_w), so the pilot's equalisation is a lead at
 * the aircraft's rate pole:
 *     Y_p = (w_c / K) (s + a_L) exp(-tau s),  a_L = max(-a, 0.3 w_c),
 * i.e. delta = delta_trim + (w_c / K) (a_L e - rate) on the error e (the
 * lead floor keeps a weakly damped axis from asking for a pure rate loop).
 * The loop stays stable while w_c tau < pi / 2 (the phase of the delay
 * eats the integrator's 90 deg margin): 0.63 s at w_c = 2.5 rad/s.
 * The outer loops, as in the multi-loop structure of Lee and Horn (2005,
 * "Simulation of pilot control activity during helicopter shipboard
 * operations", J. Aircraft 42(2), the pilot model's outer guidance
 * loops), run at separated bandwidths, each several times slower than the
 * one inside it: position -> commanded velocity (pos_bw, limited to
 * max_speed), velocity -> commanded acceleration (vel_bw), acceleration ->
 * attitude through the linear model's force derivatives
 *     theta_c = theta_trim + (a_x - X_u u) / X_theta,
 *     phi_c   = phi_trim   + (a_y - Y_v v) / Y_phi,
 * in the helicopter's heading axes, limited to max_att from trim. The
 * gains are scheduled from hfm_linearise's A and B at the task's hover in
 * the WOD of the options (uniform air), the inputs' trim from the flight.
 * The whole command vector goes through one pure delay (a ring buffer of
 * round(delay * rate) steps, filled with the trim at the start): the
 * pilot's perception and neuromuscular lag lumped, as tau in the crossover
 * model. No clock or random number inside: the same flight gives the same
 * controls.
 *
 * Assumptions: the bare airframe (the gains do not know of a SAS; fly
 * with the flight's SAS off, sim_flight_opts.sas = 0); small attitudes
 * (heading axes from the heading alone); the deck's roll and pitch are
 * not followed (the target is in S, the attitude references in E).
 *
 * Grading (ADS-33E-PRF style): the helicopter is within a band when its
 * horizontal distance from the target, its height error and its heading
 * error are all within the band's tolerances. A band is met when the
 * helicopter enters it no later than the band's time and then stays in it
 * for the task's duration.
 *
 * Landing (type land): the hover as station keeping (duration_s is the
 * stabilised hover before the descent); once it has met the desired
 * band (or the adequate one by its end) the height loop's reference moves
 * down at descent_mps (the rate fed forward) to 0.3 m below the touchdown
 * height. Touchdown is the first state with the CG at touchdown_height_m
 * above the deck (the wheels' contact, strut extended: the aircraft
 * file's [gear]); its sink rate and drift are relative to the deck (the
 * change of the position in S over the last step) and it is graded by
 * the distance from the target's x, y and the sink rate. Not modelled
 * yet: the deck-motion-aware timing (waiting for a quiescent period of
 * heave) and the collective lowered after contact.
 *
 * Task file (INI):
 *   [task]      type = station_keep | land; target_S_m = x,y,z (z < 0
 *               above the deck); heading_deg (from the bow, 0);
 *               duration_s; land: touchdown_height_m, descent_mps
 *   [desired]   pos_m, height_m, heading_deg, time_s; land: sink_mps
 *   [adequate]  the same keys, each no tighter than desired
 */
#include "sim.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define NX HFM_LIN_NX
#define NU HFM_LIN_NU
#define D2R CORE_DEG_TO_RAD

struct sim_pilot_auto {
    sim_task task;
    sim_pilot_auto_opts o;
    sim_pilot_gains g;
    double a_lead[4];        /* lead corner per axis: roll, pitch, yaw, height */
    int nbuf, head;          /* the delay's ring buffer of commands */
    double *buf;             /* nbuf x 4 */
    sim_task_result r;
    int met[2];              /* 1: the band (0 adequate, 1 desired) was met */
    int descending;          /* land: the descent is under way */
    double z_ref_S_m;        /* land: the height loop's reference (S, z down) */
    double prev_pos_S_m[3], prev_t_s; /* the last state seen (deck-relative rates) */
    int have_prev;
    sim_pilot_ref ref;       /* what the outer loops track */
    int external;            /* 1: a caller sets the reference (the phases do not) */
    double td_height_m;      /* the CG's height above the deck at wheel contact */
};

double sim_task_length_s(const sim_task *t)
{
    double T = t->adequate.time_s + t->duration_s;
    if (t->kind == SIM_TASK_LAND) /* the descent, and as long again to settle */
        T += 2.0 * fmax(-t->target_S_m[2] - t->touchdown_height_m, 0.0) / t->descent_mps + 5.0;
    return T;
}

static int tol_section(core_ini *ini, const char *s, int land, sim_task_tol *tol, core_err *err)
{
    double hd;
    int rc;
    if ((land && (rc = core_ini_get_double(ini, s, "sink_mps", 1, 0.01, 20.0, &tol->sink_mps, err))) ||(rc = core_ini_get_double(ini, s, "pos_m", 1, 0.01, 100.0, &tol->pos_m, err)) ||
        (rc = core_ini_get_double(ini, s, "height_m", 1, 0.01, 100.0, &tol->height_m, err)) ||
        (rc = core_ini_get_double(ini, s, "heading_deg", 1, 0.01, 180.0, &hd, err)) ||
        (rc = core_ini_get_double(ini, s, "time_s", 1, 0.0, 3600.0, &tol->time_s, err)))
        return rc < 0 ? rc : -1;
    tol->heading_rad = hd * D2R;
    return 0;
}

int sim_task_load(const char *path, sim_task *t, core_err *err)
{
    memset(t, 0, sizeof *t);
    core_ini *ini = core_ini_load(path, err);
    if (!ini)
        return -1;
    int kind = 0, n = 0, rc;
    double hd = 0.0;
    if ((rc = core_ini_get_enum(ini, "task", "type", 1, "station_keep|land", &kind, err)) ||
        (rc = core_ini_get_doubles(ini, "task", "target_S_m", 1, -500.0, 500.0, t->target_S_m, 3, &n, err)))
        goto out;
    if (n != 3) {
        rc = core_err_set(err, -1, "%s:%d: [task] target_S_m: expected three numbers x,y,z (m, S)", path,
                          core_ini_find(ini, "task", "target_S_m")->line);
        goto out;
    }
    if (!(t->target_S_m[2] < 0.0)) {
        rc = core_err_set(err, -1, "%s:%d: [task] target_S_m: expected z < 0 (above the deck; S is z down)", path,
                          core_ini_find(ini, "task", "target_S_m")->line);
        goto out;
    }
    if ((rc = core_ini_get_double(ini, "task", "heading_deg", 0, -180.0, 180.0, &hd, err)) < 0 ||
        (rc = core_ini_get_double(ini, "task", "duration_s", 1, 0.1, 3600.0, &t->duration_s, err)) ||
        (rc = tol_section(ini, "desired", kind == SIM_TASK_LAND, &t->desired, err)) ||
        (rc = tol_section(ini, "adequate", kind == SIM_TASK_LAND, &t->adequate, err)))
        goto out;
    if (kind == SIM_TASK_LAND) {
        if ((rc = core_ini_get_double(ini, "task", "touchdown_height_m", 1, 0.1, 20.0, &t->touchdown_height_m, err)) ||
            (rc = core_ini_get_double(ini, "task", "descent_mps", 1, 0.05, 5.0, &t->descent_mps, err)))
            goto out;
        if (!(-t->target_S_m[2] > t->touchdown_height_m)) {
            rc = core_err_set(err, -1, "%s:%d: [task] touchdown_height_m: expected below the hover's height (%.2f m)",
                              path, core_ini_find(ini, "task", "touchdown_height_m")->line, -t->target_S_m[2]);
            goto out;
        }
    }
    rc = 0;
    t->kind = kind;
    t->heading_rad = hd * D2R;
    if (t->adequate.pos_m < t->desired.pos_m || t->adequate.height_m < t->desired.height_m ||
        t->adequate.heading_rad < t->desired.heading_rad || t->adequate.time_s < t->desired.time_s ||
        t->adequate.sink_mps < t->desired.sink_mps) {
        rc = core_err_set(err, -1, "%s: [adequate]: expected each tolerance and time no tighter than [desired]'s",
                          path);
        goto out;
    }
    rc = core_ini_check_unused(ini, err);
out:
    core_ini_destroy(ini);
    return rc < 0 ? rc : (rc ? -1 : 0);
}

void sim_pilot_auto_opts_default(sim_pilot_auto_opts *o)
{
    memset(o, 0, sizeof *o);
    o->rate_hz = 200.0;
    o->delay_s = 0.25;
    o->att_crossover_radps = 2.5;
    o->yaw_crossover_radps = 1.5;
    o->hgt_crossover_radps = 1.0;
    o->vel_bw_radps = 0.8;
    o->pos_bw_radps = 0.3;
    o->max_speed_mps = 3.0;
    o->max_att_rad = 10.0 * D2R;
}

static int pos_fin(double v) { return isfinite(v) && v > 0.0; }

/* The CG's height above a level deck when the lowest wheel, strut
 * extended, touches it (the aircraft file's [gear]; 2 m without one). */
static double gear_height(const hfm_aircraft *ac)
{
    hfm_gear g;
    if (hfm_aircraft_gear(ac, &g) != 0 || g.nlegs < 1)
        return 2.0;
    double h = 0.0;
    for (int i = 0; i < g.nlegs; i++)
        h = fmax(h, g.leg[i].pos_B_m[2] + g.leg[i].tyre_radius_m);
    return h;
}

sim_pilot_auto *sim_pilot_auto_create(const hfm_aircraft *ac, const sim_task *t, const sim_pilot_auto_opts *o,
                                      const sim_flight_inputs *trim, const core_log *log, core_err *err)
{
    if (!ac || !t || !o || !trim || !(o->rate_hz >= 10.0 && o->rate_hz <= 10000.0) ||
        !(o->delay_s >= 0.0 && o->delay_s <= 10.0) || !pos_fin(o->att_crossover_radps) ||
        !pos_fin(o->yaw_crossover_radps) || !pos_fin(o->hgt_crossover_radps) || !pos_fin(o->vel_bw_radps) ||
        !pos_fin(o->pos_bw_radps) || !pos_fin(o->max_speed_mps) || !pos_fin(o->max_att_rad) ||
        !(o->wod_speed_mps >= 0.0)) {
        core_err_set(err, -1, "pilot_auto: expected an aircraft, a task, the trim, a rate of 10 to 10000 Hz, a delay "
                              "of 0 to 10 s and positive crossover frequencies, bandwidths and limits");
        return NULL;
    }
    if (t->kind != SIM_TASK_STATION_KEEP && t->kind != SIM_TASK_LAND) {
        core_err_set(err, -1, "pilot_auto: task type %d: expected station keeping (%d) or land (%d)", t->kind,
                     SIM_TASK_STATION_KEEP, SIM_TASK_LAND);
        return NULL;
    }
    if (t->kind == SIM_TASK_LAND && !(t->descent_mps > 0.0 && t->touchdown_height_m > 0.0)) {
        core_err_set(err, -1, "pilot_auto: a landing task needs a descent rate and a touchdown height > 0");
        return NULL;
    }
    sim_pilot_auto *p = calloc(1, sizeof *p);
    if (!p) {
        core_err_set(err, -1, "pilot_auto: out of memory");
        return NULL;
    }
    p->task = *t;
    p->o = *o;
    /* the gains' schedule: the hover at the target in the options' WOD */
    hfm_trim *tr = hfm_trim_create(ac, log);
    if (!tr) {
        core_err_set(err, -1, "pilot_auto: out of memory");
        goto fail;
    }
    hfm_trim_cond c;
    memset(&c, 0, sizeof c);
    c.kind = HFM_TRIM_HOVER_SHIP;
    c.wod_speed_mps = o->wod_speed_mps;
    c.wod_dir_rad = o->wod_dir_rad;
    memcpy(c.pos_S_m, t->target_S_m, sizeof c.pos_S_m);
    hfm_trim_result res;
    hfm_linear L;
    int rc = hfm_trim_solve(tr, &c, NULL, &res);
    if (rc == 0)
        rc = hfm_linearise(tr, &c, &res, &L);
    hfm_trim_destroy(tr);
    if (rc != 0) {
        core_err_set(err, -1, "pilot_auto: the hover at the task's target (%.2f, %.2f, %.2f) m in S in %.2f m/s %s",
                     t->target_S_m[0], t->target_S_m[1], t->target_S_m[2], o->wod_speed_mps,
                     rc > 0 ? "does not trim" : "could not be linearised");
        goto fail;
    }
    sim_pilot_gains *g = &p->g;
    g->X_u = L.A[0 * NX + 0];
    g->X_theta = L.A[0 * NX + 7];
    g->Y_v = L.A[1 * NX + 1];
    g->Y_phi = L.A[1 * NX + 6];
    g->Z_w = L.A[2 * NX + 2];
    g->L_p = L.A[3 * NX + 3];
    g->M_q = L.A[4 * NX + 4];
    g->N_r = L.A[5 * NX + 5];
    g->Z_col = L.B[2 * NU + 0];
    g->M_long = L.B[4 * NU + 1];
    g->L_lat = L.B[3 * NU + 2];
    g->N_ped = L.B[5 * NU + 3];
    g->trim_pct[0] = trim->collective_pct;
    g->trim_pct[1] = trim->long_pct;
    g->trim_pct[2] = trim->lat_pct;
    g->trim_pct[3] = trim->pedal_pct;
    g->trim_att_rad[0] = res.body.euler_rad[0];
    g->trim_att_rad[1] = res.body.euler_rad[1];
    const double K[4] = {g->L_lat, g->M_long, g->N_ped, g->Z_col};
    const double ctl[4] = {g->X_theta, g->Y_phi, 0.0, 0.0};
    for (int i = 0; i < 4; i++)
        if (!(fabs(K[i]) > 1e-9) || !isfinite(K[i]) || (i < 2 && !(fabs(ctl[i]) > 1e-6))) {
            core_err_set(err, -1, "pilot_auto: the linear model has no control on axis %d (derivative %g)", i, K[i]);
            goto fail;
        }
    const double a[4] = {g->L_p, g->M_q, g->N_r, g->Z_w};
    const double wc[4] = {o->att_crossover_radps, o->att_crossover_radps, o->yaw_crossover_radps,
                          o->hgt_crossover_radps};
    for (int i = 0; i < 4; i++)
        p->a_lead[i] = fmax(-a[i], 0.3 * wc[i]);
    p->nbuf = (int)lround(o->delay_s * o->rate_hz) + 1;
    if (!(p->buf = malloc((size_t)p->nbuf * 4 * sizeof *p->buf))) {
        core_err_set(err, -1, "pilot_auto: out of memory");
        goto fail;
    }
    for (int k = 0; k < p->nbuf; k++)
        memcpy(p->buf + 4 * k, g->trim_pct, sizeof g->trim_pct);
    p->r.t_desired_s = p->r.t_adequate_s = p->r.t_descent_s = p->r.t_touchdown_s = -1.0;
    p->z_ref_S_m = t->target_S_m[2];
    memcpy(p->ref.pos_S_m, t->target_S_m, sizeof p->ref.pos_S_m);
    p->ref.heading_rad = t->heading_rad;
    p->ref.mode = SIM_PILOT_HOLD;
    p->td_height_m = t->kind == SIM_TASK_LAND ? t->touchdown_height_m : gear_height(ac);
    for (int i = 0; i < 4; i++) {
        p->r.min_pct[i] = g->trim_pct[i];
        p->r.max_pct[i] = g->trim_pct[i];
    }
    return p;
fail:
    sim_pilot_auto_destroy(p);
    return NULL;
}

static int ref_ok(const sim_pilot_ref *r)
{
    for (int i = 0; i < 3; i++)
        if (!isfinite(r->pos_S_m[i]) || !isfinite(r->vel_S_mps[i]))
            return 0;
    if (!(fabs(r->heading_rad) <= M_PI) || (r->mode != SIM_PILOT_HOLD && r->mode != SIM_PILOT_DESCEND))
        return 0;
    return r->mode == SIM_PILOT_HOLD || (r->vel_S_mps[2] > 0.0 && r->vel_S_mps[2] <= 5.0);
}

/* The one way the reference changes (the phases and a caller alike): a
 * descent starts from the height reference where it is. */
static void set_ref(sim_pilot_auto *p, const sim_pilot_ref *r)
{
    if (r->mode == SIM_PILOT_HOLD)
        p->z_ref_S_m = r->pos_S_m[2];
    p->ref = *r;
}

int sim_pilot_auto_set_reference(sim_pilot_auto *p, const sim_pilot_ref *r)
{
    if (!p || !r || !ref_ok(r))
        return -1;
    p->external = 1;
    set_ref(p, r);
    return 0;
}

void sim_pilot_auto_reference(const sim_pilot_auto *p, sim_pilot_ref *r) { *r = p->ref; }

void sim_pilot_auto_destroy(sim_pilot_auto *p)
{
    if (!p)
        return;
    free(p->buf);
    free(p);
}

void sim_pilot_auto_gains(const sim_pilot_auto *p, sim_pilot_gains *g) { *g = p->g; }

void sim_pilot_auto_result(const sim_pilot_auto *p, sim_task_result *r) { *r = p->r; }

static double wrap(double a) { return atan2(sin(a), cos(a)); }

static double clampd(double v, double lo, double hi) { return fmin(fmax(v, lo), hi); }

/* Landing: the descent starts once the hover has met the desired band
 * (or, failing that, the adequate one by the hover's end); touchdown is
 * the first state with the CG at the touchdown height above the deck,
 * its sink rate and drift relative to the deck from the last two states
 * (the deck heaves with S's origin). */
static void land(sim_pilot_auto *p, const sim_flight_out *out)
{
    sim_task_result *r = &p->r;
    const sim_task *t = &p->task;
    if (!p->descending && (p->met[1] || (p->met[0] && out->t_s >= t->adequate.time_s + t->duration_s))) {
        p->descending = 1;
        r->t_descent_s = out->t_s;
        if (!p->external) {
            sim_pilot_ref d = p->ref;
            d.mode = SIM_PILOT_DESCEND;
            d.vel_S_mps[2] = t->descent_mps;
            set_ref(p, &d);
        }
    }
    if (r->touched || !p->have_prev || !(-out->pos_S_m[2] <= t->touchdown_height_m))
        return;
    double h = out->t_s - p->prev_t_s;
    if (!(h > 0.0))
        return;
    r->touched = 1;
    r->t_touchdown_s = out->t_s;
    r->sink_mps = (out->pos_S_m[2] - p->prev_pos_S_m[2]) / h;
    r->drift_mps = hypot(out->pos_S_m[0] - p->prev_pos_S_m[0], out->pos_S_m[1] - p->prev_pos_S_m[1]) / h;
    r->dist_m = hypot(out->pos_S_m[0] - t->target_S_m[0], out->pos_S_m[1] - t->target_S_m[1]);
    r->touchdown_grade = r->dist_m <= t->desired.pos_m && r->sink_mps <= t->desired.sink_mps     ? 2
                         : r->dist_m <= t->adequate.pos_m && r->sink_mps <= t->adequate.sink_mps ? 1
                                                                                                 : 0;
}

/* The grading of one step (the state the pilot sees, undelayed). */
static void grade(sim_pilot_auto *p, const sim_flight_out *out, double psi_rel)
{
    sim_task_result *r = &p->r;
    const sim_task *t = &p->task;
    if (p->descending) /* the hover's grade stands; the touchdown is graded apart */
        return;
    double dx = out->pos_S_m[0] - t->target_S_m[0], dy = out->pos_S_m[1] - t->target_S_m[1];
    r->err_pos_m = sqrt(dx * dx + dy * dy);
    r->err_height_m = -(out->pos_S_m[2] - t->target_S_m[2]);
    r->err_heading_rad = wrap(psi_rel - t->heading_rad);
    r->t_s = out->t_s;
    const sim_task_tol *band[2] = {&t->adequate, &t->desired};
    double *since[2] = {&r->t_adequate_s, &r->t_desired_s};
    for (int b = 0; b < 2; b++) {
        int in = r->err_pos_m <= band[b]->pos_m && fabs(r->err_height_m) <= band[b]->height_m &&
                 fabs(r->err_heading_rad) <= band[b]->heading_rad;
        if (!in)
            *since[b] = -1.0;
        else if (*since[b] < 0.0)
            *since[b] = out->t_s;
        if (in && *since[b] <= band[b]->time_s && out->t_s - *since[b] >= t->duration_s - 1e-9)
            p->met[b] = 1;
    }
    r->grade = p->met[1] ? 2 : p->met[0] ? 1 : 0;
    if (out->t_s >= t->desired.time_s) {
        r->max_err_pos_m = fmax(r->max_err_pos_m, r->err_pos_m);
        r->max_err_height_m = fmax(r->max_err_height_m, fabs(r->err_height_m));
        r->max_err_heading_rad = fmax(r->max_err_heading_rad, fabs(r->err_heading_rad));
    }
}

int sim_pilot_auto_step(sim_pilot_auto *p, const sim_flight_out *out, sim_flight_inputs *in)
{
    const sim_pilot_auto_opts *o = &p->o;
    const sim_pilot_gains *g = &p->g;
    const sim_task *t = &p->task;
    /* the heading relative to the ship: S's x axis in E is C_ES's first column */
    double psi_ship = atan2(out->ship.C_ES[3], out->ship.C_ES[0]);
    double psi_rel = wrap(out->euler_E_rad[2] - psi_ship);
    grade(p, out, psi_rel);
    double w_ref = 0.0;
    if (t->kind == SIM_TASK_LAND)
        land(p, out);
    const sim_pilot_ref *R = &p->ref;
    if (R->mode == SIM_PILOT_DESCEND) {
        /* the height reference moves down at the descent rate to 0.3 m
         * below the touchdown height (the wheels meet the deck on the way) */
        double z_end = -p->td_height_m + 0.3;
        if (p->z_ref_S_m < z_end) {
            p->z_ref_S_m = fmin(p->z_ref_S_m + R->vel_S_mps[2] / o->rate_hz, z_end);
            w_ref = p->z_ref_S_m < z_end ? R->vel_S_mps[2] : 0.0;
        }
    } else {
        w_ref = R->vel_S_mps[2];
    }
    memcpy(p->prev_pos_S_m, out->pos_S_m, sizeof p->prev_pos_S_m);
    p->prev_t_s = out->t_s;
    p->have_prev = 1;
    /* outer loops in the heading axes H (x forward, y right, level) */
    double c = cos(psi_rel), s = sin(psi_rel);
    double ex = R->pos_S_m[0] - out->pos_S_m[0], ey = R->pos_S_m[1] - out->pos_S_m[1];
    double eH[2] = {c * ex + s * ey, -s * ex + c * ey};
    double vH[2] = {c * out->vel_S_mps[0] + s * out->vel_S_mps[1], -s * out->vel_S_mps[0] + c * out->vel_S_mps[1]};
    double vr[2] = {c * R->vel_S_mps[0] + s * R->vel_S_mps[1], -s * R->vel_S_mps[0] + c * R->vel_S_mps[1]};
    double vc[2] = {vr[0] + o->pos_bw_radps * eH[0], vr[1] + o->pos_bw_radps * eH[1]};
    double vn = hypot(vc[0], vc[1]);
    if (vn > o->max_speed_mps)
        vc[0] *= o->max_speed_mps / vn, vc[1] *= o->max_speed_mps / vn;
    double ac[2] = {o->vel_bw_radps * (vc[0] - vH[0]), o->vel_bw_radps * (vc[1] - vH[1])};
    double th_c = g->trim_att_rad[1] + clampd((ac[0] - g->X_u * vH[0]) / g->X_theta, -o->max_att_rad, o->max_att_rad);
    double ph_c = g->trim_att_rad[0] + clampd((ac[1] - g->Y_v * vH[1]) / g->Y_phi, -o->max_att_rad, o->max_att_rad);
    /* inner loops: the crossover pilot's lead on each attitude (height) error */
    double e_att[4] = {ph_c - out->euler_E_rad[0], th_c - out->euler_E_rad[1], wrap(R->heading_rad - psi_rel),
                       p->z_ref_S_m - out->pos_S_m[2]};
    double rate[4] = {out->rate_B_radps[0], out->rate_B_radps[1], out->rate_B_radps[2], out->vel_S_mps[2] - w_ref};
    const double K[4] = {g->L_lat, g->M_long, g->N_ped, g->Z_col};
    const double wc[4] = {o->att_crossover_radps, o->att_crossover_radps, o->yaw_crossover_radps,
                          o->hgt_crossover_radps};
    static const int ch[4] = {2, 1, 3, 0}; /* axis -> control: lat, long, pedal, collective */
    double cmd[4];
    for (int i = 0; i < 4; i++)
        cmd[ch[i]] = g->trim_pct[ch[i]] + wc[i] / K[i] * (p->a_lead[i] * e_att[i] - rate[i]);
    int stop = 0;
    for (int i = 0; i < 4; i++) {
        if (!isfinite(cmd[i]))
            cmd[i] = g->trim_pct[i];
        cmd[i] = clampd(cmd[i], 0.0, 100.0);
    }
    /* the pilot's delay: the command of nbuf - 1 steps ago goes out */
    memcpy(p->buf + 4 * p->head, cmd, sizeof cmd);
    p->head = (p->head + 1) % p->nbuf;
    const double *u = p->buf + 4 * p->head;
    memset(in, 0, sizeof *in);
    in->collective_pct = u[0];
    in->long_pct = u[1];
    in->lat_pct = u[2];
    in->pedal_pct = u[3];
    for (int i = 0; i < 4; i++) {
        p->r.min_pct[i] = fmin(p->r.min_pct[i], u[i]);
        p->r.max_pct[i] = fmax(p->r.max_pct[i], u[i]);
        if (u[i] <= 0.0 || u[i] >= 100.0)
            stop = 1;
    }
    if (stop)
        p->r.stop_steps++;
    return stop;
}

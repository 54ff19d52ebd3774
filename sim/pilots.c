/* pilots.c -- the pilot stations' rules (sim_pilots): which station's
 * pilot_input_t flies the next step, a pure function of the messages
 * offered and the run clock, so that the same messages at the same run
 * steps give the same inputs in real time or as fast as it can. The rules
 * themselves are stated in sim.h beside sim_pilots.
 *
 * A buffer offered goes through disim_lcm_check_raw before lcm-gen's
 * decoder sees it (lcm 1.3.1 decodes strings without checking their NUL),
 * then through disim_lcm_check_pilot_input (NaN, range):
 * lcm_types/lcm_types.c. A buffer whose raw check fails is counted
 * against the station whose id can still be read from it.
 *
 * Hand-over. When the controls pass to a station (its first message, a
 * take-over, priority, its return after a silence, a reset) they blend
 * from the controls flown at that step to the station's, linearly over
 * SIM_PILOTS_BLEND_S, the station's own movements followed throughout:
 *   u(t) = u_flown(t0) + w (u_station(t) - u_flown(t0)),  w = (t - t0) / T.
 * A blend rather than a refusal until matched: in the aircraft the two
 * pilots' controls are linked, so "you have control" never moves them; a
 * simulator whose station controls are not back-driven fades the incoming
 * controls in instead (as it does when it leaves a freeze or a reposition)
 * and must never leave the aircraft with nobody flying, which a refusal
 * does for as long as a station (a script, a lever it cannot see) fails
 * to match. The stations of disim station start at the flown controls
 * (they read heli_state_t first), so for them the blend only smooths what
 * moved in the messages' flight; for any other it turns a step into a
 * ramp. T = 1 s: several times the attitude response's time constant (a
 * few tenths of a second), so the aircraft feels a control movement, not
 * an impulse, yet a station flies within a second of taking over. */
#include "sim.h"
#include "disim_lcm.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct station {
    sim_pilot_station s;
    int prio;          /* lower flies first */
    double in[4];      /* the last controls taken */
} station;

struct sim_pilots {
    sim_pilots_opts o;
    station st[SIM_PILOTS_MAX];
    int n, active, locked, next_order;
    long long refused_unknown;
    int flying;                /* the station whose controls flew the last step, -1: held */
    sim_pilots_blend_info b;   /* the blend */
};

void sim_pilots_opts_default(sim_pilots_opts *o)
{
    memset(o, 0, sizeof *o);
    o->hold_after_s = 0.5;
    o->blend_s = SIM_PILOTS_BLEND_S;
}

int sim_pilots_opts_parse(sim_pilots_opts *o, const char *list, core_err *err)
{
    o->n_priority = 0;
    const char *p = list;
    while (1) {
        const char *e = strchr(p, ',');
        size_t len = e ? (size_t)(e - p) : strlen(p);
        if (len == 0 || len >= SIM_STATION_ID_MAX)
            return core_err_set(err, -1, "--stations '%s': expected ids of 1 to %d characters, comma-separated", list,
                                SIM_STATION_ID_MAX - 1);
        if (o->n_priority == SIM_PILOTS_MAX)
            return core_err_set(err, -1, "--stations '%s': at most %d stations", list, SIM_PILOTS_MAX);
        memcpy(o->priority[o->n_priority], p, len);
        o->priority[o->n_priority][len] = '\0';
        for (int i = 0; i < o->n_priority; i++)
            if (!strcmp(o->priority[i], o->priority[o->n_priority]))
                return core_err_set(err, -1, "--stations '%s': '%s' appears twice", list, o->priority[i]);
        o->n_priority++;
        if (!e)
            return 0;
        p = e + 1;
    }
}

sim_pilots *sim_pilots_create(const sim_pilots_opts *o, core_err *err)
{
    if (!(o->hold_after_s > 0.0 && o->hold_after_s <= 60.0)) {
        core_err_set(err, -1, "pilot stations: hold after %g s: expected more than 0 and at most 60 s", o->hold_after_s);
        return NULL;
    }
    if (!(o->blend_s >= 0.0 && o->blend_s <= 10.0)) {
        core_err_set(err, -1, "pilot stations: blend over %g s: expected 0 to 10 s", o->blend_s);
        return NULL;
    }
    sim_pilots *p = calloc(1, sizeof *p);
    if (!p) {
        core_err_set(err, -1, "pilot stations: out of memory");
        return NULL;
    }
    p->o = *o;
    p->active = -1;
    p->flying = -1;
    p->b.station = -1;
    /* the listed stations exist from the start, in the list's order */
    for (int i = 0; i < o->n_priority; i++) {
        station *s = &p->st[p->n++];
        snprintf(s->s.id, sizeof s->s.id, "%s", o->priority[i]);
        s->s.last_seq = -1;
        s->s.heard_t_s = -1.0;
        s->prio = i;
    }
    return p;
}

void sim_pilots_destroy(sim_pilots *p) { free(p); }

static int find_station(sim_pilots *p, const char *id, int add)
{
    for (int i = 0; i < p->n; i++)
        if (!strcmp(p->st[i].s.id, id))
            return i;
    if (!add || p->n == SIM_PILOTS_MAX || p->o.n_priority > 0 || strlen(id) >= SIM_STATION_ID_MAX)
        return -1;
    station *s = &p->st[p->n];
    memset(s, 0, sizeof *s);
    snprintf(s->s.id, sizeof s->s.id, "%s", id);
    s->s.last_seq = -1;
    s->s.heard_t_s = -1.0;
    s->prio = SIM_PILOTS_MAX + 1; /* set at its first message taken */
    return p->n++;
}

/* The station id of a buffer that failed the raw check, where its bytes
 * up to the id are whole: fingerprint (8), utime (8), then the string. */
static int peek_id(const unsigned char *b, int size, char *id)
{
    if (size < 20 || !b)
        return -1;
    int64_t hash = __disim_pilot_input_t_get_hash();
    for (int i = 0; i < 8; i++)
        if (b[i] != (unsigned char)((uint64_t)hash >> (56 - 8 * i)))
            return -1;
    int32_t len = (int32_t)((uint32_t)b[16] << 24 | (uint32_t)b[17] << 16 | (uint32_t)b[18] << 8 | b[19]);
    if (len < 2 || len > SIM_STATION_ID_MAX || len > size - 20 || b[20 + len - 1] != 0)
        return -1;
    memcpy(id, b + 20, (size_t)len);
    return strlen(id) > 0 ? 0 : -1;
}

static int live(const sim_pilots *p, int i, double t_s)
{
    const station *s = &p->st[i];
    return s->s.heard_t_s >= 0.0 && t_s - s->s.heard_t_s <= p->o.hold_after_s + 1e-9;
}

static int refuse(sim_pilots *p, int i, char *why, size_t n, const char *fmt, const char *arg)
{
    if (i >= 0)
        p->st[i].s.refused++;
    else
        p->refused_unknown++;
    if (why)
        snprintf(why, n, fmt, arg);
    return 1;
}

int sim_pilots_offer(sim_pilots *p, const void *buf, int size, double t_s, char *why, size_t n)
{
    char e[256], id[SIM_STATION_ID_MAX + 1] = "";
    if (disim_lcm_check_raw("pilot_input_t", buf, size, e, sizeof e) != 0) {
        int i = peek_id(buf, size, id) == 0 ? find_station(p, id, 1) : -1;
        return refuse(p, i, why, n, "%s", e);
    }
    disim_pilot_input_t m;
    memset(&m, 0, sizeof m);
    if (disim_pilot_input_t_decode(buf, 0, size, &m) != size) {
        disim_pilot_input_t_decode_cleanup(&m);
        return refuse(p, -1, why, n, "%s", "pilot_input_t: not decoded");
    }
    int rc = 1;
    int listed = find_station(p, m.station_id, 0) >= 0;
    int i = find_station(p, m.station_id, 1);
    if (disim_lcm_check_pilot_input(&m, e, sizeof e) != 0)
        rc = refuse(p, i, why, n, "%s", e);
    else if (i < 0 && p->o.n_priority > 0 && !listed)
        rc = refuse(p, -1, why, n, "pilot_input_t from '%s': not on the station list", m.station_id);
    else if (i < 0)
        rc = refuse(p, -1, why, n, "pilot_input_t from '%s': too many stations", m.station_id);
    else {
        station *s = &p->st[i];
        /* both seqs are >= 0 (checked), so their difference cannot overflow */
        int64_t ahead = s->s.last_seq >= 0 ? m.seq - s->s.last_seq : 0;
        if (s->s.last_seq >= 0 && ahead <= 0 && live(p, i, t_s))
            rc = refuse(p, i, why, n, "pilot_input_t from '%s': seq not above the last (stale)", s->s.id);
        else if (s->s.last_seq >= 0 && ahead <= 0 && m.seq >= SIM_PILOTS_RESTART_SEQ_MAX)
            rc = refuse(p, i, why, n, "pilot_input_t from '%s': seq not above the last after a silence, and too "
                                      "high for a restart (a replay)", s->s.id);
        else if (ahead > SIM_PILOTS_SEQ_JUMP_MAX)
            rc = refuse(p, i, why, n, "pilot_input_t from '%s': seq jumps more than 1000000 past the last "
                                      "(a spoofed or corrupt message)", s->s.id);
        else {
            /* a low seq at or below the last after a silence: the
             * station restarted; its count starts again there */
            if (ahead > 1)
                s->s.gaps += ahead - 1;
            if (s->s.received == 0 && p->o.n_priority == 0)
                s->prio = p->next_order++;
            s->s.last_seq = m.seq;
            s->s.heard_t_s = t_s;
            s->s.received++;
            s->in[0] = m.collective_pct;
            s->in[1] = m.long_cyclic_pct;
            s->in[2] = m.lat_cyclic_pct;
            s->in[3] = m.pedal_pct;
            if (m.take_over) {
                p->active = i;
                p->locked = 1;
            }
            rc = 0;
        }
    }
    disim_pilot_input_t_decode_cleanup(&m);
    return rc;
}

/* The active station's controls into in, blended from the flown ones
 * when the controls have just passed to it or a blend runs. */
static void fly_station(sim_pilots *p, double t_s, const hfm_controls *flown, sim_flight_inputs *in)
{
    const station *s = &p->st[p->active];
    sim_pilots_blend_info *b = &p->b;
    if (p->flying != p->active && p->o.blend_s > 0.0) {
        b->blending = 1;
        b->station = p->active;
        b->t0_s = t_s;
        b->from_pct[0] = flown->collective_pct;
        b->from_pct[1] = flown->long_cyclic_pct;
        b->from_pct[2] = flown->lat_cyclic_pct;
        b->from_pct[3] = flown->pedal_pct;
        b->started++;
    }
    p->flying = p->active;
    double w = b->blending ? (t_s - b->t0_s) / p->o.blend_s : 1.0;
    if (w >= 1.0 - 1e-9) {
        w = 1.0;
        b->blending = 0;
    }
    double u[4];
    for (int k = 0; k < 4; k++)
        u[k] = w >= 1.0 ? s->in[k] : b->from_pct[k] + w * (s->in[k] - b->from_pct[k]);
    in->ctl.collective_pct = u[0];
    in->ctl.long_cyclic_pct = u[1];
    in->ctl.lat_cyclic_pct = u[2];
    in->ctl.pedal_pct = u[3];
}

int sim_pilots_inputs(sim_pilots *p, double t_s, const hfm_controls *flown, sim_flight_inputs *in)
{
    memset(in, 0, sizeof *in);
    if (p->locked && (p->active < 0 || !live(p, p->active, t_s)))
        p->locked = 0;
    if (!p->locked) {
        int best = -1;
        for (int i = 0; i < p->n; i++)
            if (live(p, i, t_s) && (best < 0 || p->st[i].prio < p->st[best].prio))
                best = i;
        if (best >= 0 && (p->active < 0 || p->st[best].prio < p->st[p->active].prio))
            p->active = best;
    }
    if (p->active >= 0 && live(p, p->active, t_s)) {
        fly_station(p, t_s, flown, in);
        return 0;
    }
    p->flying = -1; /* held: the next station to fly blends in */
    p->b.blending = 0;
    in->hold = 1;
    return 1;
}

void sim_pilots_reblend(sim_pilots *p) { p->flying = -1; }
void sim_pilots_blend(const sim_pilots *p, sim_pilots_blend_info *b) { *b = p->b; }
int sim_pilots_count(const sim_pilots *p) { return p->n; }
void sim_pilots_station(const sim_pilots *p, int i, sim_pilot_station *s)
{
    *s = p->st[i].s;
    memcpy(s->in_pct, p->st[i].in, sizeof s->in_pct);
}
int sim_pilots_active(const sim_pilots *p) { return p->active; }
long long sim_pilots_refused_unknown(const sim_pilots *p) { return p->refused_unknown; }

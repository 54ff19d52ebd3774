/* aw_client.c -- a test client of `disim airwaked` over LCM: publishes one
 * airwake request (ship-only SFS2 head wind) and waits up to T seconds for
 * the builder's status READY for that ship and speed, printing every status.
 * Usage: aw_client SPEED_MPS TIMEOUT_S [bad|loaded] ("bad": a request with
 * a negative speed, which must come back FAILED naming the field;
 * "loaded": a loaded-disk request, which the message cannot describe (no
 * blade loads), so it must come back FAILED naming rotor, not be queued;
 * "raw": a request whose ship string lacks its NUL, published as raw bytes,
 * which must be refused before decoding, naming the field). */
#include "disim_lcm.h"

#include <lcm/lcm.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

typedef struct st {
    double speed;
    int ready, failed, accepted;
    char msg[256];
    const char *id; /* the request's id */
} st;

static void on_status(const lcm_recv_buf_t *rb, const char *ch, const disim_airwake_status_t *m, void *u)
{
    (void)rb;
    (void)ch;
    st *s = u;
    printf("aw_client: status %d %s %.2f m/s %.0f%% res %.2e it %d %s %s\n", m->state, m->ship, m->wod_speed_mps,
           100 * m->progress, m->residual, m->iterations, m->path, m->message);
    if (!strcmp(m->request_id, "loaded-1") && !strcmp(s->id, "loaded-1")) {
        if (m->state == DISIM_AIRWAKE_STATUS_T_FAILED) {
            s->failed = 1;
            snprintf(s->msg, sizeof s->msg, "%s", m->message);
        } else
            s->accepted = 1;
        return;
    }
    if (!strcmp(s->id, "raw-1")) { /* refused unread: no id to echo */
        if (m->state == DISIM_AIRWAKE_STATUS_T_FAILED && strstr(m->message, "airwake_request_t.ship")) {
            s->failed = 1;
            snprintf(s->msg, sizeof s->msg, "%s", m->message);
        } else if (!strcmp(m->ship, "SFS2"))
            s->accepted = 1;
        return;
    }
    if (strcmp(m->ship, "SFS2") && strcmp(m->request_id, "bad-1"))
        return;
    if (m->state == DISIM_AIRWAKE_STATUS_T_READY && fabs(m->wod_speed_mps - s->speed) < 0.01)
        s->ready = 1;
    if (m->state == DISIM_AIRWAKE_STATUS_T_FAILED) {
        s->failed = 1;
        snprintf(s->msg, sizeof s->msg, "%s", m->message);
    }
}

int main(int argc, char **argv)
{
    if (argc < 3)
        return 2;
    int timeout = atoi(argv[2]), bad = argc > 3 && !strcmp(argv[3], "bad");
    int loaded = argc > 3 && !strcmp(argv[3], "loaded"), raw = argc > 3 && !strcmp(argv[3], "raw");
    st s = {atof(argv[1]), 0, 0, 0, "", bad ? "bad-1" : loaded ? "loaded-1" : raw ? "raw-1" : "req-1"};
    lcm_t *lc = lcm_create(NULL);
    if (!lc)
        return 1;
    disim_airwake_status_t_subscription_t *sub =
        disim_airwake_status_t_subscribe(lc, DISIM_CH_AIRWAKE_STATUS, on_status, &s);
    disim_airwake_request_t rq;
    memset(&rq, 0, sizeof rq);
    rq.request_id = (char *)s.id;
    rq.ship = "SFS2";
    rq.aircraft = "";
    rq.wod_speed_mps = bad ? -3.0 : s.speed;
    rq.wod_dir_rad = 0.0;
    rq.rotor = DISIM_AIRWAKE_REQUEST_T_ROTOR_OFF;
    if (loaded) { /* otherwise a valid rotor-on request */
        rq.aircraft = "UH-60A";
        rq.rotor = DISIM_AIRWAKE_REQUEST_T_ROTOR_LOADED;
        rq.rotor_thrust_N = 72950.0;
        rq.rotor_radius_m = 8.18;
        rq.station_S_m[2] = -6.0;
    }
    rq.grid = "coarse";
    time_t t0 = time(NULL), last = 0;
    while (time(NULL) - t0 < timeout && !s.ready && !s.failed && !s.accepted) {
        if (time(NULL) - last >= 2) { /* repeat until heard: the builder may still be starting */
            rq.utime = (int64_t)time(NULL) * 1000000;
            if (raw) {
                /* the ship's NUL overwritten: fingerprint 8, utime 8, seq 8,
                 * request_id 4 + 6, then the ship's length and "SFS2\0" */
                int n = disim_airwake_request_t_encoded_size(&rq);
                unsigned char *b = malloc(n);
                disim_airwake_request_t_encode(b, 0, n, &rq);
                b[8 + 8 + 8 + 4 + 6 + 4 + 4] = 'x';
                lcm_publish(lc, DISIM_CH_AIRWAKE_REQUEST, b, n);
                free(b);
            } else
                disim_airwake_request_t_publish(lc, DISIM_CH_AIRWAKE_REQUEST, &rq);
            last = time(NULL);
        }
        lcm_handle_timeout(lc, 200);
    }
    disim_airwake_status_t_unsubscribe(lc, sub);
    lcm_destroy(lc);
    if (loaded) {
        printf("aw_client: loaded request %s: %s\n", s.failed ? "refused" : s.accepted ? "ACCEPTED" : "not answered",
               s.msg);
        return s.failed && strstr(s.msg, "rotor") ? 0 : 1;
    }
    if (raw) {
        printf("aw_client: unterminated string %s: %s\n", s.failed ? "refused" : s.accepted ? "ACCEPTED" : "not answered",
               s.msg);
        return s.failed && strstr(s.msg, "without its NUL") ? 0 : 1;
    }
    if (bad) {
        printf("aw_client: bad request %s: %s\n", s.failed ? "refused" : "NOT refused", s.msg);
        return s.failed && strstr(s.msg, "wod_speed_mps") ? 0 : 1;
    }
    printf("aw_client: %s\n", s.ready ? "ready" : "timed out");
    return s.ready ? 0 : 1;
}

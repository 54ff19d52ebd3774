/* lcm_xproc.c -- one side of the cross-process test over UDP multicast:
 * `lcm_xproc sub N` waits (up to 10 s) for N helicopter states with the
 * sequence numbers 0..N-1 in order; `lcm_xproc pub N` publishes them every
 * 20 ms; `lcm_xproc count S` counts the helicopter states of any sender
 * that reach it in S seconds and prints the count. Each opens LCM at
 * disim's URL (disim_lcm_url: LCM_DEFAULT_URL, else ttl 0). Run only inside
 * private network namespaces (lcm_xproc.sh, lcm_ttl.sh). */
#include "disim_lcm.h"

#include <lcm/lcm.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static void on_any(const lcm_recv_buf_t *rb, const char *ch, const disim_heli_state_t *m, void *u)
{
    (void)rb;
    (void)ch;
    (void)m;
    (*(int *)u)++;
}

typedef struct rx {
    int next;
    int bad;
} rx;

static void on_state(const lcm_recv_buf_t *rb, const char *ch, const disim_heli_state_t *m, void *u)
{
    (void)rb;
    (void)ch;
    rx *r = u;
    if (m->seq != r->next || m->collective_pct != 50.0 + m->seq || m->n_gear != 3)
        r->bad++;
    r->next = (int)m->seq + 1;
}

int main(int argc, char **argv)
{
    if (argc != 3 || (strcmp(argv[1], "pub") && strcmp(argv[1], "sub") && strcmp(argv[1], "count"))) {
        fprintf(stderr, "usage: lcm_xproc pub|sub N | count SECONDS\n");
        return 2;
    }
    int n = atoi(argv[2]);
    lcm_t *lc = lcm_create(disim_lcm_url(NULL));
    if (!lc) {
        fprintf(stderr, "lcm_xproc: lcm_create failed\n");
        return 1;
    }
    int rc = 0;
    if (!strcmp(argv[1], "count")) {
        int got = 0;
        disim_heli_state_t_subscription_t *sub = disim_heli_state_t_subscribe(lc, DISIM_CH_HELI_STATE, on_any, &got);
        time_t t0 = time(NULL);
        while (time(NULL) - t0 < n)
            lcm_handle_timeout(lc, 200);
        printf("%d\n", got);
        disim_heli_state_t_unsubscribe(lc, sub);
    } else if (!strcmp(argv[1], "pub")) {
        double gear[3] = {1, 2, 3};
        for (int i = 0; i < n; i++) {
            disim_heli_state_t m = {0};
            m.utime = i * 20000;
            m.seq = i;
            m.collective_pct = 50.0 + i;
            m.n_gear = 3;
            m.gear_load_N = gear;
            m.quat_EB[0] = 1.0;
            if (disim_heli_state_t_publish(lc, DISIM_CH_HELI_STATE, &m) != 0)
                rc = 1;
            struct timespec ts = {0, 20000000};
            nanosleep(&ts, NULL);
        }
    } else {
        rx r = {0, 0};
        disim_heli_state_t_subscription_t *sub =
            disim_heli_state_t_subscribe(lc, DISIM_CH_HELI_STATE, on_state, &r);
        time_t t0 = time(NULL);
        while (r.next < n && time(NULL) - t0 < 10)
            lcm_handle_timeout(lc, 200);
        printf("lcm_xproc: received %d of %d, %d out of order or wrong\n", r.next, n, r.bad);
        rc = (r.next == n && r.bad == 0) ? 0 : 1;
        disim_heli_state_t_unsubscribe(lc, sub);
    }
    lcm_destroy(lc);
    return rc;
}

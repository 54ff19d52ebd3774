/* soak.h -- the classes of hostile traffic of the flight loop's soak
 * (soak_tx sends them, soak_check counts them again in the loop's log). */
#ifndef DISIM_SOAK_H
#define DISIM_SOAK_H

enum {
    SOAK_PILOT_RANDOM,
    SOAK_PILOT_TRUNC,
    SOAK_PILOT_NAN,
    SOAK_PILOT_HUGE,
    SOAK_PILOT_REPLAY,
    SOAK_PILOT_AHEAD,
    SOAK_PILOT_TAKEOVER,
    SOAK_PILOT_FLOOD,
    SOAK_CTL_RANDOM,
    SOAK_CTL_TRUNC,
    SOAK_CTL_BAD,
    SOAK_CTL_GOOD,
    SOAK_CTL_BURST,
    SOAK_HELI_GARBAGE,
    SOAK_STATUS_GARBAGE,
    SOAK_AWREQ_GARBAGE,
    SOAK_NCLASS
};

static const char *const soak_class_name[SOAK_NCLASS] = {
    "pilot_random", "pilot_trunc",  "pilot_nan", "pilot_huge", "pilot_replay",   "pilot_ahead",
    "pilot_takeover", "pilot_flood", "ctl_random", "ctl_trunc", "ctl_bad",       "ctl_good",
    "ctl_burst",    "heli_garbage", "status_garbage", "awreq_garbage"};

/* A control's seq: its class in bits 40 and up, its number below. */
#define SOAK_SEQ_SHIFT 40
#define SOAK_SEQ(cls, n) ((long long)((cls) + 1) << SOAK_SEQ_SHIFT | (long long)(n))
/* The class of a control's seq, or -1 (not the soak's: disim ios, another). */
static inline int soak_seq_class(long long seq)
{
    long long c = seq >> SOAK_SEQ_SHIFT;
    return seq >= 0 && c >= 1 && c <= SOAK_NCLASS ? (int)c - 1 : -1;
}

#endif

/*
 * disim_lcm.h -- the LCM message types of package disim and their channels.
 *
 * Channel names are upper case with the DISIM_ prefix (docs/conventions.md).
 * Every message carries utime (simulation microseconds) and a sequence
 * number.
 * disim_lcm_check_* validate a received message before use: they return 0 if
 * every field is finite and in range, else < 0 with err naming the field.
 */
#ifndef DISIM_LCM_H
#define DISIM_LCM_H

#include "disim_heli_state_t.h"
#include "disim_ship_state_t.h"
#include "disim_pilot_input_t.h"
#include "disim_sim_control_t.h"
#include "disim_sim_status_t.h"
#include "disim_airwake_request_t.h"
#include "disim_airwake_status_t.h"
#include "disim_shol_point_t.h"
#include "disim_run_info_t.h"

#include <stddef.h>

#define DISIM_CH_HELI_STATE "DISIM_HELI_STATE"
#define DISIM_CH_SHIP_STATE "DISIM_SHIP_STATE"
#define DISIM_CH_PILOT_INPUT "DISIM_PILOT_INPUT"
#define DISIM_CH_SIM_CONTROL "DISIM_SIM_CONTROL"
#define DISIM_CH_SIM_STATUS "DISIM_SIM_STATUS"
#define DISIM_CH_AIRWAKE_REQUEST "DISIM_AIRWAKE_REQUEST"
#define DISIM_CH_AIRWAKE_STATUS "DISIM_AIRWAKE_STATUS"
#define DISIM_CH_SHOL_POINT "DISIM_SHOL_POINT"
#define DISIM_CH_RUN_INFO "DISIM_RUN_INFO"

/* The URL every disim process opens LCM with unless told otherwise: UDP
 * multicast with a time-to-live of 0, so that no datagram leaves this host
 * (docs/conventions.md). Reaching stations on other hosts is a choice made
 * on every process (--lcm URL with ttl=1, or LCM_DEFAULT_URL), and it opens
 * the simulator to every host on that network (README, "Stations on other
 * hosts"). */
#define DISIM_LCM_DEFAULT_URL "udpm://239.255.76.67:7667?ttl=0"

/* The URL to open: given (a --lcm flag) when not NULL, else the
 * environment's LCM_DEFAULT_URL when set and not empty, else
 * DISIM_LCM_DEFAULT_URL. */
const char *disim_lcm_url(const char *given);

int disim_lcm_check_pilot_input(const disim_pilot_input_t *m, char *err, size_t n);
/* The loop's states as every receiver takes them (the view, the stations,
 * the log reader): utime >= 0, positions, velocities, angles and rates
 * finite and within physical bounds, the quaternion of unit norm (within
 * 1e-6 of its square), the controls 0 to 100 %, thrust, power and every
 * gear load finite. 0, or -1 with err "heli_state_t.FIELD (expected ...)". */
int disim_lcm_check_heli_state(const disim_heli_state_t *m, char *err, size_t n);
/* The same for a ship state: position, velocity, rates finite and within
 * bounds, the quaternion of unit norm, the spot's motion finite. */
int disim_lcm_check_ship_state(const disim_ship_state_t *m, char *err, size_t n);
int disim_lcm_check_sim_control(const disim_sim_control_t *m, char *err, size_t n);
int disim_lcm_check_airwake_request(const disim_airwake_request_t *m, char *err, size_t n);

/* Check a received buffer of type TYPE ("airwake_request_t", ...; the
 * fingerprint first, as lcm_recv_buf_t holds it) before decoding it: every
 * string must have a length of at least 1 ending in its NUL inside the
 * message and no other NUL (it decodes to the bytes received), every count
 * be >= 0, and the size be what the fields take. lcm
 * 1.3.1's decoder checks none of this, so a hostile or broken sender could
 * leave a decoded string unterminated. 0 ok; -1 with err naming the field;
 * -2 for a type that is not disim's. Subscribe with lcm_subscribe, check,
 * then disim_T_decode. */
int disim_lcm_check_raw(const char *type, const void *buf, int size, char *err, size_t n);
/* A message of an older version of TYPE (sim_control_t, sim_status_t:
 * fields appended since) rewritten as the newest into out (cap bytes), the
 * fields it lacks at their defaults (as each .lcm says), so that a log of
 * an older disim reads: the new size; 0 when buf is not of an older
 * version (use it as it is); -1 when out is too small. */
int disim_lcm_upgrade(const char *type, const void *buf, int size, void *out, int cap);

#endif

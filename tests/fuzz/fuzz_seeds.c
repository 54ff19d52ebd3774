/* fuzz_seeds.c -- writes the seed corpora of the harnesses that take
 * binary input, made with the project's own encoders and writers (so that
 * a seed is what disim really sends or writes): under DIR,
 *   lcm_msg/      one encoded message of every type, with the harness's
 *                 type byte first (pilot_input_t as a run of length-prefixed
 *                 buffers: in order, a gap, stale, a jump, a NaN)
 *   sim_control/  one encoded sim_control_t of every command
 *   lcm_log/      a short LCM log of a run (run_info_t, heli_state_t,
 *                 ship_state_t, pilot_input_t, sim_status_t, sim_control_t)
 *   awdb/         the database's records by awdb_key_format, with the
 *                 harness's kind byte first (0 a request, 1 a checksum
 *                 record): ship-only, a uniform rotor, a loaded rotor, a zone
 *   field/        a small airwake field (a 4 x 3 x 2-cell channel after a
 *                 few solver iterations) by cfd_solver_write, checksum in
 * tests/fuzz/seeds.sh runs it and adds the repository's text files.
 * Usage: fuzz_seeds DIR */
#include "awdb_private.h"
#include "cfd.h"
#include "disim_lcm.h"

#include <lcm/lcm.h>

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static const char *root;

static void put(const char *sub, const char *name, const unsigned char *b, size_t n)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", root, sub);
    if (mkdir(path, 0755) != 0 && errno != EEXIST) {
        perror(path);
        exit(1);
    }
    snprintf(path, sizeof path, "%s/%s/%s", root, sub, name);
    FILE *f = fopen(path, "wb");
    if (!f || fwrite(b, 1, n, f) != n || fclose(f) != 0) {
        perror(path);
        exit(1);
    }
}

/* encode m of type T into b (after `pre` bytes), its size */
#define ENC(T, b, pre, m) (pre + disim_##T##_encode((b) + (pre), 0, (int)sizeof(b) - (pre), (m)))

static disim_heli_state_t heli(long long k)
{
    disim_heli_state_t h;
    memset(&h, 0, sizeof h);
    static double gear[3] = {0.0, 0.0, 0.0};
    h.utime = k * 5000;
    h.seq = k;
    h.pos_S_m[0] = -20.0 + 0.01 * (double)k;
    h.pos_S_m[2] = -10.0;
    h.quat_EB[0] = 1.0;
    h.collective_pct = 55.0;
    h.long_cyclic_pct = h.lat_cyclic_pct = h.pedal_pct = 50.0;
    h.rotor_thrust_N = 70000.0;
    h.rotor_power_W = 1.2e6;
    h.n_gear = 3;
    h.gear_load_N = gear;
    return h;
}

static disim_ship_state_t ship(long long k)
{
    disim_ship_state_t s;
    memset(&s, 0, sizeof s);
    s.utime = k * 5000;
    s.seq = k;
    s.quat_ES[0] = 1.0;
    s.vel_E_mps[0] = 7.7;
    return s;
}

static disim_pilot_input_t pilot(const char *id, long long seq, double coll)
{
    disim_pilot_input_t p;
    memset(&p, 0, sizeof p);
    p.utime = seq < 1000000000LL ? seq * 20000 : 0;
    p.station_id = (char *)id;
    p.seq = seq;
    p.collective_pct = coll;
    p.long_cyclic_pct = p.lat_cyclic_pct = p.pedal_pct = 50.0;
    return p;
}

static disim_sim_control_t control(int cmd, const char *path, const char *name)
{
    disim_sim_control_t c;
    memset(&c, 0, sizeof c);
    c.seq = cmd;
    c.command = (int8_t)cmd;
    c.scenario_path = (char *)path;
    c.pos_S_m[0] = -15.0;
    c.pos_S_m[2] = -8.0;
    c.wod_speed_mps = 12.0;
    c.wod_dir_rad = 0.5;
    c.sea_state = 3;
    c.turbulence = 1;
    c.name = (char *)name;
    return c;
}

static disim_sim_status_t status(void)
{
    static char *ids[2] = {"A", "B"};
    static int64_t last[2] = {10, 3}, rec[2] = {11, 4}, ref[2] = {0, 2}, gaps[2] = {0, 1};
    disim_sim_status_t s;
    memset(&s, 0, sizeof s);
    s.sim_time_s = 1.0;
    s.rate_hz = 200.0;
    s.real_time_factor = 1.0;
    s.state = DISIM_SIM_STATUS_T_RUNNING;
    s.scenario = "cg47_uh60a";
    s.n_stations = 2;
    s.station_ids = ids;
    s.station_last_seq = last;
    s.station_received = rec;
    s.station_refused = ref;
    s.station_gaps = gaps;
    s.message = "";
    s.control_seq = -1;
    s.control_message = "";
    return s;
}

static disim_run_info_t info(void)
{
    disim_run_info_t r;
    memset(&r, 0, sizeof r);
    r.scenario_path = "scenarios/cg47_uh60a.ini";
    r.scenario = "cg47_uh60a";
    r.aircraft_path = "scenarios/aircraft/uh60a.ini";
    r.ship_path = "scenarios/ships/cg47.ini";
    r.seed = 1;
    r.sea_state = 3;
    r.ship_speed_mps = 7.7;
    r.wod_speed_mps = 12.9;
    r.rate_hz = 200.0;
    r.state_rate_hz = 50.0;
    return r;
}

static void lcm_msg_seeds(void)
{
    unsigned char b[4096];
    int n;
    /* pilot_input_t: length-prefixed buffers offered in turn */
    long long seqs[] = {0, 1, 2, 5, 5, 3, 2000000, 6, 9223372036854775807LL, 7};
    int pos = 1;
    b[0] = 0;
    for (size_t i = 0; i < sizeof seqs / sizeof seqs[0]; i++) {
        disim_pilot_input_t p = pilot(i == 7 ? "B" : "A", seqs[i], i == 9 ? 0.0 / 0.0 : 50.0 + (double)i);
        p.take_over = i == 7;
        n = disim_pilot_input_t_encode(b + pos + 2, 0, (int)sizeof b - pos - 2, &p);
        b[pos] = (unsigned char)(n >> 8);
        b[pos + 1] = (unsigned char)n;
        pos += 2 + n;
    }
    put("lcm_msg", "pilot_input_t", b, (size_t)pos);
    b[0] = 1;
    disim_sim_control_t c = control(DISIM_SIM_CONTROL_T_LOAD_SCENARIO, "scenarios/cg47_uh60a.ini", "");
    put("lcm_msg", "sim_control_t", b, (size_t)ENC(sim_control_t, b, 1, &c));
    b[0] = 2;
    disim_heli_state_t h = heli(3);
    put("lcm_msg", "heli_state_t", b, (size_t)ENC(heli_state_t, b, 1, &h));
    b[0] = 3;
    disim_ship_state_t s = ship(3);
    put("lcm_msg", "ship_state_t", b, (size_t)ENC(ship_state_t, b, 1, &s));
    b[0] = 4;
    disim_sim_status_t st = status();
    put("lcm_msg", "sim_status_t", b, (size_t)ENC(sim_status_t, b, 1, &st));
    b[0] = 5;
    disim_run_info_t ri = info();
    put("lcm_msg", "run_info_t", b, (size_t)ENC(run_info_t, b, 1, &ri));
    b[0] = 6;
    disim_airwake_request_t rq;
    memset(&rq, 0, sizeof rq);
    rq.request_id = "r1";
    rq.ship = "CG-47";
    rq.aircraft = "UH-60A";
    rq.wod_speed_mps = 15.0;
    rq.wod_dir_rad = -0.5;
    rq.rotor = DISIM_AIRWAKE_REQUEST_T_ROTOR_UNIFORM;
    rq.rotor_thrust_N = 70000.0;
    rq.station_S_m[0] = -2.0;
    rq.station_S_m[2] = -6.0;
    rq.rotor_radius_m = 8.18;
    rq.grid = "coarse";
    put("lcm_msg", "airwake_request_t", b, (size_t)ENC(airwake_request_t, b, 1, &rq));
    b[0] = 7;
    disim_airwake_status_t as;
    memset(&as, 0, sizeof as);
    as.request_id = "r1";
    as.ship = "CG-47";
    as.aircraft = "UH-60A";
    as.state = DISIM_AIRWAKE_STATUS_T_READY;
    as.progress = 1.0;
    as.iterations = 600;
    as.path = "out/airwake-db/fields/x.h5";
    as.message = "";
    put("lcm_msg", "airwake_status_t", b, (size_t)ENC(airwake_status_t, b, 1, &as));
    b[0] = 8;
    disim_shol_point_t sp;
    memset(&sp, 0, sizeof sp);
    sp.ship = "CG-47";
    sp.aircraft = "UH-60A";
    sp.converged = 1;
    sp.limit = "";
    sp.collective_pct = 55.0;
    put("lcm_msg", "shol_point_t", b, (size_t)ENC(shol_point_t, b, 1, &sp));
}

static void sim_control_seeds(void)
{
    unsigned char b[2048];
    for (int cmd = DISIM_SIM_CONTROL_T_PAUSE; cmd <= DISIM_SIM_CONTROL_T_RESTORE; cmd++) {
        const char *path = cmd == DISIM_SIM_CONTROL_T_LOAD_SCENARIO ? "tests/sim/data/loop_a.ini" : "";
        const char *name = cmd == DISIM_SIM_CONTROL_T_SNAPSHOT || cmd == DISIM_SIM_CONTROL_T_RESTORE ? "s1" : "";
        disim_sim_control_t c = control(cmd, path, name);
        char file[32];
        snprintf(file, sizeof file, "command_%02d", cmd);
        put("sim_control", file, b, (size_t)ENC(sim_control_t, b, 0, &c));
    }
}

static void log_event(lcm_eventlog_t *lg, const char *ch, const unsigned char *b, int n, long long k)
{
    lcm_eventlog_event_t ev;
    memset(&ev, 0, sizeof ev);
    ev.timestamp = 1700000000000000LL + k * 5000;
    ev.channellen = (int32_t)strlen(ch);
    ev.channel = (char *)ch;
    ev.datalen = n;
    ev.data = (void *)b;
    if (lcm_eventlog_write_event(lg, &ev) != 0) {
        fprintf(stderr, "fuzz_seeds: cannot write the log\n");
        exit(1);
    }
}

static void lcm_log_seeds(void)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/lcm_log", root);
    if (mkdir(path, 0755) != 0 && errno != EEXIST) {
        perror(path);
        exit(1);
    }
    snprintf(path, sizeof path, "%s/lcm_log/run.lcm", root);
    lcm_eventlog_t *lg = lcm_eventlog_create(path, "w");
    if (!lg) {
        perror(path);
        exit(1);
    }
    unsigned char b[2048];
    disim_run_info_t ri = info();
    log_event(lg, DISIM_CH_RUN_INFO, b, disim_run_info_t_encode(b, 0, sizeof b, &ri), 0);
    for (long long k = 0; k < 6; k++) {
        disim_pilot_input_t p = pilot("A", k, 55.0);
        log_event(lg, DISIM_CH_PILOT_INPUT, b, disim_pilot_input_t_encode(b, 0, sizeof b, &p), k);
        disim_heli_state_t h = heli(k);
        log_event(lg, DISIM_CH_HELI_STATE, b, disim_heli_state_t_encode(b, 0, sizeof b, &h), k);
        disim_ship_state_t s = ship(k);
        log_event(lg, DISIM_CH_SHIP_STATE, b, disim_ship_state_t_encode(b, 0, sizeof b, &s), k);
    }
    disim_sim_control_t c = control(DISIM_SIM_CONTROL_T_PAUSE, "", "");
    log_event(lg, DISIM_CH_SIM_CONTROL, b, disim_sim_control_t_encode(b, 0, sizeof b, &c), 6);
    disim_sim_status_t st = status();
    log_event(lg, DISIM_CH_SIM_STATUS, b, disim_sim_status_t_encode(b, 0, sizeof b, &st), 6);
    lcm_eventlog_destroy(lg);
}

static void field_seeds(void)
{
    core_err err = {0};
    cfd_config cfg;
    cfd_config_default(&cfg);
    cfg.turbulence = 1;
    cfg.nu_m2ps = 1e-3;
    cfg.bc[CFD_XMIN].type = CFD_BC_INLET;
    cfg.bc[CFD_XMAX].type = CFD_BC_OUTLET;
    cfg.inflow.vel_mps[0] = 1.0;
    cfg.max_iter = 3;
    cfd_axis_spec ax[3] = {{0, 4, 0, 4, 1.0, 1.0, 1.0}, {0, 1, 0, 1, 0.34, 0.34, 1.0}, {0, 1, 0, 1, 0.5, 0.5, 1.0}};
    cfd_grid *g = cfd_grid_create_spec(ax, &err);
    cfd_solver *s = g ? cfd_solver_create(g, &cfg, &err) : NULL;
    cfd_result res;
    if (!s || cfd_solver_run(s, &res, &err) < 0) {
        fprintf(stderr, "fuzz_seeds: the field: %s\n", err.msg);
        exit(1);
    }
    cfd_meta meta;
    memset(&meta, 0, sizeof meta);
    meta.wod_speed_mps = 1.0;
    meta.wod_dir_deg = -30.0;
    snprintf(meta.ship, sizeof meta.ship, "channel");
    snprintf(meta.rotor, sizeof meta.rotor, "off");
    snprintf(meta.grid, sizeof meta.grid, "test");
    meta.result = res;
    char path[1024];
    snprintf(path, sizeof path, "%s/field", root);
    if (mkdir(path, 0755) != 0 && errno != EEXIST) {
        perror(path);
        exit(1);
    }
    snprintf(path, sizeof path, "%s/field/channel.h5", root);
    if (cfd_solver_write(s, &meta, path, &err) != 0) {
        fprintf(stderr, "fuzz_seeds: %s\n", err.msg);
        exit(1);
    }
    snprintf(path, sizeof path, "%s/field/channel.xmf", root);
    remove(path); /* the XDMF side file is not read */
    cfd_solver_destroy(s);
}

static void awdb_seeds(void)
{
    for (int i = 0; i < 4; i++) {
        awdb_key k;
        memset(&k, 0, sizeof k);
        snprintf(k.ship, sizeof k.ship, "%s", i == 3 ? "CG-47.isolated" : "CG-47");
        snprintf(k.aircraft, sizeof k.aircraft, "%s", i == 0 ? "" : "UH-60A");
        k.wod_speed_mps = 15.0;
        k.wod_dir_rad = -0.5236;
        k.grid = CORE_GRID_COARSE;
        k.rotor = i == 1 ? CORE_ROTOR_UNIFORM : i == 2 ? CORE_ROTOR_LOADED : CORE_ROTOR_OFF;
        k.station_S_m[0] = -2.0;
        k.station_S_m[2] = -6.0;
        k.radius_m = i ? 8.18 : 0.0;
        k.thrust_N = k.rotor != CORE_ROTOR_OFF ? 72950.0 : 0.0;
        k.zone_ref_mps = i == 3 ? 15.0 : 0.0;
        if (k.rotor == CORE_ROTOR_LOADED) {
            for (int j = 0; j < AWDB_LOAD_NR * AWDB_LOAD_NPSI; j++)
                k.load[j] = 1.0;
            for (int j = 0; j < AWDB_LOAD_NR; j++)
                k.swirl[j] = 0.5;
            k.torque_Nm = 35000.0;
            k.root_cut = 0.1;
            k.ccw_from_above = 1;
        }
        char text[8192], name[32];
        text[0] = 0;
        awdb_key_format(&k, text + 1, sizeof text - 1);
        snprintf(name, sizeof name, "request_%d", i);
        put("awdb", name, (const unsigned char *)text, strlen(text + 1) + 1);
        char sum[8400];
        sum[0] = 1;
        int n = snprintf(sum + 1, sizeof sum - 1, "[field]\nsize = 123456\ncrc64 = 0123456789abcdef\n\n%s", text + 1);
        snprintf(name, sizeof name, "sum_%d", i);
        put("awdb", name, (const unsigned char *)sum, (size_t)n + 1);
    }
}

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: fuzz_seeds DIR\n");
        return 2;
    }
    root = argv[1];
    if (mkdir(root, 0755) != 0 && errno != EEXIST) {
        perror(root);
        return 1;
    }
    lcm_msg_seeds();
    sim_control_seeds();
    lcm_log_seeds();
    field_seeds();
    awdb_seeds();
    return 0;
}

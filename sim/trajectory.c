/* trajectory.c -- a flight's trajectory as CSV (sim_traj): one row of a
 * step's outputs (sim_flight_out) every rate_hz / row_rate_hz steps, its
 * columns named in the header (the CG in S, the attitudes in E in
 * degrees, the velocity in S, the CG in E, the controls, the air's flags,
 * the rotor's thrust and power, the gear's contact, load and flags).
 * Written to PATH.tmpPID and renamed at sim_traj_commit, so that a run
 * that failed or stopped leaves nothing half-written. */
#include "sim.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

struct sim_traj {
    FILE *f;
    long every;            /* a row every so many steps */
    char tmp[SIM_PATH_MAX + 32]; /* the temporary, "" once renamed */
    char path[SIM_PATH_MAX];
};

sim_traj *sim_traj_create(const char *path, double rate_hz, double row_rate_hz, core_err *err)
{
    if (!path || strlen(path) >= SIM_PATH_MAX || !(rate_hz > 0.0) || !(row_rate_hz > 0.0)) {
        core_err_set(err, -1, "trajectory: expected a path under %d characters and rates above 0", SIM_PATH_MAX);
        return NULL;
    }
    sim_traj *t = calloc(1, sizeof *t);
    if (!t) {
        core_err_set(err, -1, "trajectory: out of memory");
        return NULL;
    }
    t->every = (long)fmax(1.0, llround(rate_hz / row_rate_hz));
    snprintf(t->path, sizeof t->path, "%s", path);
    snprintf(t->tmp, sizeof t->tmp, "%s.tmp%ld", path, (long)getpid());
    if (!(t->f = fopen(t->tmp, "w"))) {
        core_err_set(err, -1, "%s: cannot write the trajectory: %s (its temporary %s)", path, strerror(errno), t->tmp);
        free(t);
        return NULL;
    }
    fprintf(t->f, "t_s,x_S_m,y_S_m,z_S_m,roll_deg,pitch_deg,yaw_deg,u_S_mps,v_S_mps,w_S_mps,x_E_m,y_E_m,z_E_m,"
                  "collective_pct,long_pct,lat_pct,pedal_pct,air_flags,rotor_thrust_N,rotor_power_W,on_deck,gear_load_N,"
                  "contact_flags\n");
    return t;
}

int sim_traj_row(sim_traj *t, const sim_flight_out *o, int always, core_err *err)
{
    if (!t || !(always || o->step % t->every == 0))
        return 0;
    double gear_N = 0.0; /* the legs' loads along the deck normal, summed */
    for (int i = 0; i < o->nlegs; i++)
        gear_N += o->gear_load_N[i];
    if (fprintf(t->f,
                "%.4f,%.4f,%.4f,%.4f,%.5f,%.5f,%.5f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.3f,%.3f,%.3f,%.3f,%u,%.1f,%.1f,"
                "%d,%.1f,%u\n",
                o->t_s, o->pos_S_m[0], o->pos_S_m[1], o->pos_S_m[2], o->euler_E_rad[0] * CORE_RAD_TO_DEG,
                o->euler_E_rad[1] * CORE_RAD_TO_DEG, o->euler_E_rad[2] * CORE_RAD_TO_DEG, o->vel_S_mps[0],
                o->vel_S_mps[1], o->vel_S_mps[2], o->pos_E_m[0], o->pos_E_m[1], o->pos_E_m[2], o->ctl.collective_pct,
                o->ctl.long_cyclic_pct, o->ctl.lat_cyclic_pct, o->ctl.pedal_pct, o->air_flags, o->rotor_thrust_N,
                o->rotor_power_W, o->on_deck, gear_N, o->contact_flags) < 0)
        return core_err_set(err, -1, "%s: cannot write the trajectory: %s (nothing written)", t->path,
                            strerror(errno));
    return 0;
}

int sim_traj_commit(sim_traj *t, core_err *err)
{
    if (!t || !t->f)
        return 0;
    errno = 0;
    int bad = fflush(t->f) != 0 || ferror(t->f) || fsync(fileno(t->f)) != 0;
    int e = errno;
    bad |= fclose(t->f) != 0;
    if (!e)
        e = errno;
    t->f = NULL;
    if (!bad && rename(t->tmp, t->path) != 0) {
        bad = 1;
        e = errno;
    }
    if (bad)
        return core_err_set(err, -1, "%s: cannot write the trajectory: %s (nothing written)", t->path,
                            e ? strerror(e) : "a write failed");
    t->tmp[0] = '\0';
    return 0;
}

void sim_traj_destroy(sim_traj *t)
{
    if (!t)
        return;
    if (t->f)
        fclose(t->f);
    if (t->tmp[0])
        unlink(t->tmp);
    free(t);
}

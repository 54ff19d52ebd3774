/* ship_frame.c -- the ship stage's frames of S in E for the flight's steps,
 * and the deck's motion the gear needs.
 *
 * The frames: a frame is a sum over the seaway's waves, and the flight
 * model's integrator samples the air at hundreds of points at each of a
 * step's stage times. The ship stage therefore computes the frames at the
 * step times k h around the step under way once per step, one new frame
 * each step, and every other time is had from them: a step time (as the
 * loop computes it, k h, within 1e-12 of it) is its frame; a time between
 * two step times is interpolated linearly between theirs. The error is of
 * order (h w)^2 of the motion for a step h and a motion of frequency w:
 * below 1e-5 of it at 200 Hz for the ship's periods of 5 s and more.
 *
 * The deck's motion at t: the frame there and S's velocities, by central
 * differences of the frame over 1e-4 s (any sim_ship_frame_fn), the
 * angular velocity from Omega_x = dC/dt C^T.
 */
#include "sim.h"

#include <math.h>
#include <string.h>

int sim_ship_frames_advance(sim_ship_frames *fs, sim_ship_frame_fn frame, void *user, double h_s, long step)
{
    if (!(h_s > 0.0))
        return -1;
    int keep = 0; /* frames of the last window still in this one, moved down */
    if (fs->n == SIM_SHIP_FRAMES && fs->h_s == h_s && step >= fs->step && step - fs->step < SIM_SHIP_FRAMES) {
        keep = SIM_SHIP_FRAMES - (int)(step - fs->step);
        memmove(fs->fr, fs->fr + (SIM_SHIP_FRAMES - keep), (size_t)keep * sizeof fs->fr[0]);
    }
    fs->n = 0;
    fs->h_s = h_s;
    fs->step = step;
    for (int i = keep; i < SIM_SHIP_FRAMES; i++)
        if (frame(user, (double)(step - 1 + i) * h_s, &fs->fr[i]))
            return -1;
    fs->n = SIM_SHIP_FRAMES;
    return 0;
}

/* The frame at step k, or NULL outside the window. */
static const sim_ship_frame *frame_of_step(const sim_ship_frames *fs, double k)
{
    double i = k - (double)(fs->step - 1);
    if (fs->n != SIM_SHIP_FRAMES || !(i >= 0.0 && i < SIM_SHIP_FRAMES))
        return NULL;
    return &fs->fr[(int)i];
}

int sim_ship_frames_at(const sim_ship_frames *fs, double t_s, sim_ship_frame *fr)
{
    const double h = fs->h_s;
    if (fs->n != SIM_SHIP_FRAMES || !isfinite(t_s))
        return -1;
    /* a step time (k h, as the loop computes it) is exact; floor alone
     * would put 3 h / h = 2.9999... in the step before */
    double kn = nearbyint(t_s / h);
    if (fabs(t_s - kn * h) <= 1e-12 * fmax(1.0, fabs(t_s))) {
        const sim_ship_frame *p = frame_of_step(fs, kn);
        if (!p)
            return -1;
        *fr = *p;
        return 0;
    }
    double k = floor(t_s / h), t0 = k * h;
    const sim_ship_frame *f0 = frame_of_step(fs, k), *f1 = frame_of_step(fs, k + 1.0);
    if (!f0 || !f1)
        return -1;
    double w = (t_s - t0) / h;
    for (int i = 0; i < 3; i++) {
        fr->origin_E_m[i] = (1.0 - w) * f0->origin_E_m[i] + w * f1->origin_E_m[i];
        fr->mean_vel_E_mps[i] = (1.0 - w) * f0->mean_vel_E_mps[i] + w * f1->mean_vel_E_mps[i];
    }
    for (int i = 0; i < 9; i++)
        fr->C_ES[i] = (1.0 - w) * f0->C_ES[i] + w * f1->C_ES[i];
    return 0;
}

int sim_ship_frames_fn(void *user, double t_s, sim_ship_frame *fr)
{
    return sim_ship_frames_at(user, t_s, fr);
}

int sim_ship_deck_at(sim_ship_frame_fn frame, void *user, double t_s, sim_ship_deck *d)
{
    sim_ship_frame a, b;
    const double dt = 1e-4;
    if (frame(user, t_s, &d->fr) || frame(user, t_s - dt, &a) || frame(user, t_s + dt, &b))
        return -1;
    const sim_ship_frame *fr = &d->fr;
    double W[3][3];
    for (int i = 0; i < 3; i++)
        d->vel_E_mps[i] = (b.origin_E_m[i] - a.origin_E_m[i]) / (2 * dt);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double s = 0;
            for (int k = 0; k < 3; k++)
                s += (b.C_ES[3 * i + k] - a.C_ES[3 * i + k]) / (2 * dt) * fr->C_ES[3 * j + k];
            W[i][j] = s;
        }
    d->omega_E_radps[0] = 0.5 * (W[2][1] - W[1][2]);
    d->omega_E_radps[1] = 0.5 * (W[0][2] - W[2][0]);
    d->omega_E_radps[2] = 0.5 * (W[1][0] - W[0][1]);
    return 0;
}

/* S still, level, at E's origin. */
static int still_frame(void *user, double t_s, sim_ship_frame *fr)
{
    (void)user;
    (void)t_s;
    memset(fr, 0, sizeof *fr);
    fr->C_ES[0] = fr->C_ES[4] = fr->C_ES[8] = 1.0;
    return 0;
}

void sim_ship_deck_still(sim_ship_deck *d) { sim_ship_deck_at(still_frame, NULL, 0.0, d); }

/* camera.c -- the cameras, the views and the one projection.
 *
 * A view is an eye and two unit axes in E (forward, up) with a vertical
 * field of view. render_gl_matrices builds the GL projection and model-view
 * matrices from it (the GL world of render_priv.h: W = (x_E - o_x,
 * -(z_E - o_z), y_E - o_y)); render_frame loads them and render_project
 * pushes points through the very same matrices, so a projected point and
 * the rasterised pixel agree (the tests depend on it). The projection is
 * gluPerspective's (symmetric frustum, aspect w/h) and the model-view is
 * gluLookAt's with the camera's right = forward x up (in E, right-handed:
 * looking north with up -z_E, right is east).
 *
 * Cameras (render_camera_place):
 *   pilot    the eye at the aircraft file's pilot_eye_B_m, looking along
 *            body x pitched 10 deg down, up = body -z (pitched the same);
 *            fov 60 deg;
 *   deck     the landing officer on the deck at its aft starboard corner,
 *            S (deck_x0_m + 2, deck_halfwidth_m - 1, -1.7), ship-fixed (up
 *            is S's -z: the horizon moves as the ship rolls), looking at
 *            the helicopter's CG (the spot without one); fov 70 deg (at 50 a rotor 8 m off filled it);
 *   chase    25 m behind and 8 m above the CG along the helicopter's
 *            heading (yaw only), looking at the CG, up = E's -z; fov 55 deg
 *            (without a helicopter: the spot and the ship's heading);
 *   overhead ship-fixed, 60 m straight above the spot (S z = -60), looking
 *            down S's +z with the bow up in the image; fov 40 deg.
 * Clip planes 0.2 m and 8000 m (the horizon haze is complete well inside). */
#include "render_priv.h"

#include <math.h>
#include <string.h>

#define CAM_NEAR_M 0.2
#define CAM_FAR_M 8000.0

static const char *const cam_names[RENDER_CAM_COUNT] = {"pilot", "deck", "chase", "overhead"};

int render_camera_parse(const char *name, render_camera_kind *kind, core_err *err)
{
    for (int k = 0; name && k < RENDER_CAM_COUNT; k++)
        if (strcmp(name, cam_names[k]) == 0) {
            *kind = (render_camera_kind)k;
            return 0;
        }
    return core_err_set(err, -1, "render: camera '%s': expected pilot, deck, chase or overhead",
                        name ? name : "(null)");
}

const char *render_camera_name(render_camera_kind kind)
{
    return (int)kind >= 0 && kind < RENDER_CAM_COUNT ? cam_names[kind] : "?";
}

static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static void cross3(const double a[3], const double b[3], double c[3])
{
    double t[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    memcpy(c, t, sizeof t);
}

static int finite3(const double a[3]) { return isfinite(a[0]) && isfinite(a[1]) && isfinite(a[2]); }

int render_view_check(const render_view *v, core_err *err)
{
    if (!v)
        return core_err_set(err, -1, "render: view: NULL");
    if (!finite3(v->eye_E_m))
        return core_err_set(err, -1, "render: view eye_E_m (%g, %g, %g): expected finite values", v->eye_E_m[0],
                            v->eye_E_m[1], v->eye_E_m[2]);
    if (!finite3(v->fwd_E) || !finite3(v->up_E))
        return core_err_set(err, -1, "render: view fwd_E/up_E: expected finite values");
    double nf = sqrt(dot3(v->fwd_E, v->fwd_E)), nu = sqrt(dot3(v->up_E, v->up_E));
    if (fabs(nf - 1.0) > 1e-6)
        return core_err_set(err, -1, "render: view fwd_E has length %.9g: expected a unit vector", nf);
    if (fabs(nu - 1.0) > 1e-6)
        return core_err_set(err, -1, "render: view up_E has length %.9g: expected a unit vector", nu);
    if (fabs(dot3(v->fwd_E, v->up_E)) > 1e-6)
        return core_err_set(err, -1, "render: view fwd_E . up_E = %.3g: expected orthogonal axes",
                            dot3(v->fwd_E, v->up_E));
    if (!(v->fov_y_deg >= 1.0 && v->fov_y_deg <= 170.0))
        return core_err_set(err, -1, "render: view fov_y_deg = %g: expected 1 to 170", v->fov_y_deg);
    if (!(v->near_m > 0.0 && isfinite(v->near_m) && v->far_m > v->near_m && isfinite(v->far_m)))
        return core_err_set(err, -1, "render: view near_m = %g, far_m = %g: expected 0 < near < far", v->near_m,
                            v->far_m);
    return 0;
}

/* E vector to the GL world's axes (render_priv.h). */
static void e_to_w(const double e[3], double w[3])
{
    w[0] = e[0];
    w[1] = -e[2];
    w[2] = e[1];
}

void render_gl_matrices(const render_view *v, int w, int h, const double origin_E_m[3], double proj[16],
                        double mv[16])
{
    /* gluPerspective, column-major. */
    double f = 1.0 / tan(0.5 * v->fov_y_deg * CORE_DEG_TO_RAD), aspect = (double)w / h;
    double n = v->near_m, fa = v->far_m;
    memset(proj, 0, 16 * sizeof *proj);
    proj[0] = f / aspect;
    proj[5] = f;
    proj[10] = (fa + n) / (n - fa);
    proj[11] = -1.0;
    proj[14] = 2.0 * fa * n / (n - fa);
    /* gluLookAt: rows s (right), u (up), -f; the eye relative to origin. */
    double right_E[3], s[3], u[3], fw[3], eye_E[3], e[3];
    cross3(v->fwd_E, v->up_E, right_E);
    e_to_w(right_E, s);
    e_to_w(v->up_E, u);
    e_to_w(v->fwd_E, fw);
    for (int i = 0; i < 3; i++)
        eye_E[i] = v->eye_E_m[i] - origin_E_m[i];
    e_to_w(eye_E, e);
    double m[16] = {s[0], u[0], -fw[0], 0, s[1], u[1], -fw[1], 0, s[2], u[2], -fw[2], 0,
                    -dot3(s, e), -dot3(u, e), dot3(fw, e), 1};
    memcpy(mv, m, sizeof m);
}

int render_project(const render_view *v, int w, int h, const double p_E_m[3], double px[2], double *depth_m)
{
    double proj[16], mv[16], pw[3], rel[3];
    /* The eye as origin: the same matrices as the frame's, less the
     * rounding of a far origin. */
    render_gl_matrices(v, w, h, v->eye_E_m, proj, mv);
    for (int i = 0; i < 3; i++)
        rel[i] = p_E_m[i] - v->eye_E_m[i];
    e_to_w(rel, pw);
    double eye[4], clip[4];
    for (int r = 0; r < 4; r++)
        eye[r] = mv[r] * pw[0] + mv[4 + r] * pw[1] + mv[8 + r] * pw[2] + mv[12 + r];
    for (int r = 0; r < 4; r++)
        clip[r] = proj[r] * eye[0] + proj[4 + r] * eye[1] + proj[8 + r] * eye[2] + proj[12 + r] * eye[3];
    double d = -eye[2];
    if (depth_m)
        *depth_m = d;
    if (!(d > v->near_m) || !(clip[3] > 0.0)) {
        px[0] = px[1] = NAN;
        return -1;
    }
    double nx = clip[0] / clip[3], ny = clip[1] / clip[3];
    px[0] = 0.5 * (nx + 1.0) * w;
    px[1] = 0.5 * (1.0 - ny) * h; /* GL's window y runs up; the image's rows run down */
    if (d > v->far_m || !(px[0] >= 0.0 && px[0] < w && px[1] >= 0.0 && px[1] < h))
        return 1;
    return 0;
}

void render_S_to_E(const render_state *s, const double p_S_m[3], double p_E_m[3])
{
    core_vec3 p = core_pose_point_to_E(&s->ship, core_vec3_make(p_S_m[0], p_S_m[1], p_S_m[2]));
    p_E_m[0] = p.x, p_E_m[1] = p.y, p_E_m[2] = p.z;
}

void render_B_to_E(const render_state *s, const double p_B_m[3], double p_E_m[3])
{
    core_vec3 p = core_pose_point_to_E(&s->heli, core_vec3_make(p_B_m[0], p_B_m[1], p_B_m[2]));
    p_E_m[0] = p.x, p_E_m[1] = p.y, p_E_m[2] = p.z;
}

static void vec_to_E(const core_pose *f, const double v_F[3], double v_E[3])
{
    core_vec3 r = core_pose_vec_to_E(f, core_vec3_make(v_F[0], v_F[1], v_F[2]));
    v_E[0] = r.x, v_E[1] = r.y, v_E[2] = r.z;
}

static int normalize3(double a[3])
{
    double n = sqrt(dot3(a, a));
    if (!(n > 1e-12) || !isfinite(n))
        return -1;
    for (int i = 0; i < 3; i++)
        a[i] /= n;
    return 0;
}

/* A view from eye along fwd (need not be unit) with up_hint made
 * orthogonal to it (Gram-Schmidt); alt_up when up_hint is along fwd. */
static int view_from(render_view *v, const double eye[3], const double fwd[3], const double up_hint[3],
                     const double alt_up[3], double fov_deg, core_err *err)
{
    double f[3] = {fwd[0], fwd[1], fwd[2]}, u[3];
    if (!finite3(eye) || !finite3(fwd) || normalize3(f) != 0)
        return core_err_set(err, -1, "render: view from eye (%g, %g, %g): no direction to look in (eye on its "
                            "target, or not finite)", eye[0], eye[1], eye[2]);
    for (int pass = 0; pass < 2; pass++) {
        const double *h = pass == 0 ? up_hint : alt_up;
        double d = dot3(h, f);
        for (int i = 0; i < 3; i++)
            u[i] = h[i] - d * f[i];
        if (sqrt(dot3(u, u)) > 1e-3 && normalize3(u) == 0)
            break;
        if (pass == 1)
            return core_err_set(err, -1, "render: view: up is along the direction of view");
    }
    memcpy(v->eye_E_m, eye, sizeof v->eye_E_m);
    memcpy(v->fwd_E, f, sizeof v->fwd_E);
    memcpy(v->up_E, u, sizeof v->up_E);
    v->fov_y_deg = fov_deg;
    v->near_m = CAM_NEAR_M;
    v->far_m = CAM_FAR_M;
    return render_view_check(v, err);
}

int render_view_look_at(render_view *v, const double eye_E_m[3], const double target_E_m[3], double fov_y_deg,
                        core_err *err)
{
    if (!finite3(eye_E_m) || !finite3(target_E_m))
        return core_err_set(err, -1, "render: look-at eye_E_m/target_E_m: expected finite values");
    double f[3] = {target_E_m[0] - eye_E_m[0], target_E_m[1] - eye_E_m[1], target_E_m[2] - eye_E_m[2]};
    if (!(sqrt(dot3(f, f)) > 1e-3))
        return core_err_set(err, -1, "render: look-at eye_E_m (%g, %g, %g) is on target_E_m: expected them apart",
                            eye_E_m[0], eye_E_m[1], eye_E_m[2]);
    /* Straight down or up: north is up in the image. */
    static const double up_E[3] = {0, 0, -1}, north[3] = {1, 0, 0};
    return view_from(v, eye_E_m, f, up_E, north, fov_y_deg, err);
}

int render_camera_place(render_camera_kind kind, const render_scene *sc, const render_state *s, render_view *v,
                        core_err *err)
{
    if (!sc || !sc->ship || !s || !v)
        return core_err_set(err, -1, "render: camera: expected a scene with a ship, a state and a view");
    const core_ship *sh = sc->ship;
    double eye[3], tgt[3], fwd[3], up[3], alt[3];
    switch (kind) {
    case RENDER_CAM_PILOT: {
        if (!sc->heli || !sc->heli->has_eye)
            return core_err_set(err, -1, "render: the pilot camera needs an aircraft with [cockpit] "
                                "pilot_eye_B_m (%s)", sc->heli ? sc->heli->name : "no aircraft in the scene");
        if (!s->have_heli)
            return core_err_set(err, -1, "render: the pilot camera needs the helicopter's state (have_heli 0)");
        double p = 10.0 * CORE_DEG_TO_RAD;
        double f_B[3] = {cos(p), 0, sin(p)}, u_B[3] = {sin(p), 0, -cos(p)}, a_B[3] = {1, 0, 0};
        render_B_to_E(s, sc->heli->eye_B_m, eye);
        vec_to_E(&s->heli, f_B, fwd);
        vec_to_E(&s->heli, u_B, up);
        vec_to_E(&s->heli, a_B, alt);
        return view_from(v, eye, fwd, up, alt, 60.0, err);
    }
    case RENDER_CAM_DECK: {
        double e_S[3] = {sh->deck_x0_m + 2.0, sh->deck_halfwidth_m - 1.0, -1.7}, o_S[3] = {0, 0, 0};
        double u_S[3] = {0, 0, -1}, a_S[3] = {1, 0, 0};
        render_S_to_E(s, e_S, eye);
        if (s->have_heli)
            tgt[0] = s->heli.pos_E_m.x, tgt[1] = s->heli.pos_E_m.y, tgt[2] = s->heli.pos_E_m.z;
        else
            render_S_to_E(s, o_S, tgt);
        for (int i = 0; i < 3; i++)
            fwd[i] = tgt[i] - eye[i];
        vec_to_E(&s->ship, u_S, up);
        vec_to_E(&s->ship, a_S, alt);
        return view_from(v, eye, fwd, up, alt, 70.0, err);
    }
    case RENDER_CAM_CHASE: {
        double psi;
        if (s->have_heli) {
            tgt[0] = s->heli.pos_E_m.x, tgt[1] = s->heli.pos_E_m.y, tgt[2] = s->heli.pos_E_m.z;
            double xb[3] = {1, 0, 0}, xe[3];
            vec_to_E(&s->heli, xb, xe);
            /* The heading of the body x axis; the state's yaw where the nose
             * points straight up or down. */
            psi = hypot(xe[0], xe[1]) > 1e-6 ? atan2(xe[1], xe[0]) : s->yaw_rad;
        } else {
            double o_S[3] = {0, 0, 0}, xs[3] = {1, 0, 0}, xe[3];
            render_S_to_E(s, o_S, tgt);
            vec_to_E(&s->ship, xs, xe);
            psi = atan2(xe[1], xe[0]);
        }
        eye[0] = tgt[0] - 25.0 * cos(psi);
        eye[1] = tgt[1] - 25.0 * sin(psi);
        eye[2] = tgt[2] - 8.0;
        double u_E[3] = {0, 0, -1}, a_E[3] = {cos(psi), sin(psi), 0};
        for (int i = 0; i < 3; i++)
            fwd[i] = tgt[i] - eye[i];
        return view_from(v, eye, fwd, u_E, a_E, 55.0, err);
    }
    case RENDER_CAM_OVERHEAD: {
        double e_S[3] = {0, 0, -60.0}, f_S[3] = {0, 0, 1}, u_S[3] = {1, 0, 0};
        render_S_to_E(s, e_S, eye);
        vec_to_E(&s->ship, f_S, fwd);
        vec_to_E(&s->ship, u_S, up);
        return view_from(v, eye, fwd, up, up, 40.0, err);
    }
    default:
        return core_err_set(err, -1, "render: camera kind %d: expected 0 to %d", (int)kind, RENDER_CAM_COUNT - 1);
    }
}

/* scene.c -- the 3-D scene of a frame: sky, sea, ship with its flight deck,
 * helicopter; one sun.
 *
 * Model (fixed-function OpenGL 1.x, flat-shaded solids, as a simple flight
 * simulator's visual):
 *  - The GL world of render_priv.h, its origin at the state's landing spot.
 *  - Light: one directional sun fixed in E (azimuth 140 deg, elevation
 *    50 deg) of diffuse SCN_DIFFUSE and an ambient SCN_AMBIENT, summing to
 *    1: a surface facing the sun shows its render_colour_rgb colour, one
 *    facing away SCN_AMBIENT of it. Haze: exponential-squared fog toward
 *    the sky's horizon colour (4 % at 400 m, 63 % at 2 km, 95 % at 3.5 km), so the sea
 *    fades into the sky at the horizon.
 *  - Sky: a dome about the eye, fixed in E, its colour from the horizon's
 *    (at and below the horizon) to the zenith's as sin(elevation)^0.6.
 *  - Sea: a grid of SEA_N x SEA_N vertices over SEA_SIDE_M square in E about
 *    the ship (its centre snapped to the grid's spacing so the vertices do
 *    not swim as the ship moves), its elevation from the scene's sea
 *    function, called once a frame with every vertex; normals by central
 *    differences; the waves taper to the mean level over the grid's outer
 *    tenth, where a flat sea takes over out to SEA_FAR_M. The mean surface
 *    is z_E = deck_height_m (E's origin is S's mean position, the spot
 *    deck_height_m above the waterline), a wave eta (up) at deck_height_m -
 *    eta.
 *  - Ship: every block, each vertex through the ship's pose (S to E); the
 *    flight deck's markings drawn on it with a polygon offset: the
 *    non-skid deck, the deck-edge lines and the line-up line (the centre
 *    line from the aft edge to the hangar), the landing circle with a spot
 *    at its centre, deck-edge lights, the hangar door on the hangar face
 *    (the block rising from the deck's forward end), and a horizon
 *    reference bar on the hangar top held level in E (gyro-stabilised: it
 *    rolls against the ship and shows the true horizon).
 *  - Helicopter (hfm_geometry, body axes from the CG, placed by the state's
 *    pose): a cabin from the nose (the strike point "nose", else 0.62 R
 *    ahead of the CG) with a tapered nose, an engine fairing and mast, a
 *    tail boom to the tail rotor, a fin, the stabiliser; the main rotor as
 *    a translucent disk of radius R at the hub, tilted forward by the shaft
 *    tilt, with its blades at the state's azimuth turning as rotor_ccw
 *    says (blade 1 at azimuth psi along -cos(psi) forward + sin(psi)
 *    right in the disk, counter-clockwise from above: over the tail at 0,
 *    to starboard at 90 deg; starboard and port swapped for a clockwise
 *    rotor); an open tail rotor (a disk normal to tail_dir_B with blades) or
 *    a fenestron (a ducted ring in the fin); the gear's struts and wheels.
 *    Proportions not in the aircraft file are fractions of R (stated where
 *    used): a recognisable silhouette, not a survey.
 * The translucent disks are drawn last, after the airwake overlay, with
 * depth writes off. */
#include "render_priv.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ------------------------------------------------------------- colours */
static const uint8_t colour_table[RENDER_COLOUR_COUNT][3] = {
    [RENDER_COLOUR_SKY_ZENITH] = {62, 112, 190},  [RENDER_COLOUR_SKY_HORIZON] = {172, 196, 220},
    [RENDER_COLOUR_SEA] = {22, 58, 92},           [RENDER_COLOUR_HULL] = {150, 156, 162},
    [RENDER_COLOUR_DECK] = {66, 68, 70},          [RENDER_COLOUR_MARKING] = {236, 236, 230},
    [RENDER_COLOUR_SPOT] = {235, 200, 40},        [RENDER_COLOUR_LIGHT] = {255, 236, 150},
    [RENDER_COLOUR_HORIZON_BAR] = {60, 255, 90},  [RENDER_COLOUR_FUSELAGE] = {98, 108, 72},
    [RENDER_COLOUR_ROTOR] = {34, 34, 38},
};

double render_rotor_azimuth(const hfm_geometry *g, double t_s)
{
    double a = fmod(g->rotor_omega_radps * t_s, 2.0 * CORE_PI);
    return g->rotor_ccw ? a : -a;
}

void render_colour_rgb(render_colour c, uint8_t rgb[3])
{
    if ((int)c < 0 || c >= RENDER_COLOUR_COUNT) {
        rgb[0] = rgb[1] = rgb[2] = 0;
        return;
    }
    memcpy(rgb, colour_table[c], 3);
}

#define SCN_AMBIENT 0.4
#define SCN_DIFFUSE 0.6
#define SUN_AZ_DEG 140.0
#define SUN_EL_DEG 50.0
#define FOG_DENSITY_PER_M 5.0e-4
#define SEA_N 97
#define SEA_SIDE_M 800.0
#define SEA_FAR_M 7000.0
#define SKY_R_M 4000.0

/* Where a frame's vertices come from: E, S (the ship) or B (the body). */
enum { FR_E = 0, FR_S = 1, FR_B = 2 };

typedef struct scn {
    render_ctx *rc;
    const render_scene *sc;
    const render_state *s;
    double R[3][3][3]; /* frame -> E rotations (row major) */
    double t[3][3];    /* frame origins in E */
} scn;

static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static void cross3(const double a[3], const double b[3], double c[3])
{
    double t[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
    memcpy(c, t, sizeof t);
}

static int unit3(double a[3])
{
    double n = sqrt(dot3(a, a));
    if (!(n > 1e-12))
        return -1;
    a[0] /= n, a[1] /= n, a[2] /= n;
    return 0;
}

static void quat_to_R(core_quat q, double R[3][3])
{
    /* The columns are the frame's axes in E (core_quat_rotate of the unit
     * vectors), so the matrix agrees with core_pose_point_to_E. */
    core_vec3 ax[3] = {core_quat_rotate(q, core_vec3_make(1, 0, 0)), core_quat_rotate(q, core_vec3_make(0, 1, 0)),
                       core_quat_rotate(q, core_vec3_make(0, 0, 1))};
    for (int c = 0; c < 3; c++)
        R[0][c] = ax[c].x, R[1][c] = ax[c].y, R[2][c] = ax[c].z;
}

static void to_E(const scn *d, int fr, const double p[3], double e[3])
{
    const double(*R)[3] = d->R[fr];
    for (int r = 0; r < 3; r++)
        e[r] = R[r][0] * p[0] + R[r][1] * p[1] + R[r][2] * p[2] + d->t[fr][r];
}

static void vec_E(const scn *d, int fr, const double v[3], double e[3])
{
    const double(*R)[3] = d->R[fr];
    for (int r = 0; r < 3; r++)
        e[r] = R[r][0] * v[0] + R[r][1] * v[1] + R[r][2] * v[2];
}

static void vtx(const scn *d, int fr, const double p[3])
{
    double e[3];
    to_E(d, fr, p, e);
    render_gl_vertex_E(d->rc, e);
}

static void vtx3(const scn *d, int fr, double x, double y, double z)
{
    double p[3] = {x, y, z};
    vtx(d, fr, p);
}

static void nrm(const scn *d, int fr, const double n[3])
{
    double e[3];
    vec_E(d, fr, n, e);
    render_gl_normal_E(e);
}

static void colour(render_colour c, double scale, double alpha)
{
    const uint8_t *k = colour_table[c];
    glColor4d(k[0] / 255.0 * scale, k[1] / 255.0 * scale, k[2] / 255.0 * scale, alpha);
}

/* A flat quad (one normal, from its diagonals, pointing away from inside:
 * a point of the solid it bounds). */
static void quad_in(const scn *d, int fr, const double *p0, const double *p1, const double *p2, const double *p3,
                    const double inside[3])
{
    double a[3], b[3], n[3], c[3];
    for (int i = 0; i < 3; i++) {
        a[i] = p2[i] - p0[i];
        b[i] = p3[i] - p1[i];
        c[i] = 0.25 * (p0[i] + p1[i] + p2[i] + p3[i]) - inside[i];
    }
    cross3(a, b, n);
    if (unit3(n) != 0)
        return; /* degenerate (a taper's point) */
    if (dot3(n, c) < 0)
        n[0] = -n[0], n[1] = -n[1], n[2] = -n[2];
    nrm(d, fr, n);
    vtx(d, fr, p0);
    vtx(d, fr, p1);
    vtx(d, fr, p2);
    vtx(d, fr, p3);
}

/* A hexahedron from 8 corners, corner index = x bit (0 aft, 1 forward) |
 * y bit << 1 (0 port, 1 starboard) | z bit << 2 (0 top, 1 bottom). */
static void hexa(const scn *d, int fr, const double c[8][3])
{
    static const int face[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1}, {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
    double in[3] = {0, 0, 0};
    for (int k = 0; k < 8; k++)
        for (int i = 0; i < 3; i++)
            in[i] += c[k][i] / 8.0;
    glBegin(GL_QUADS);
    for (int f = 0; f < 6; f++)
        quad_in(d, fr, c[face[f][0]], c[face[f][1]], c[face[f][2]], c[face[f][3]], in);
    glEnd();
}

/* A box tapered along x: at x0 half-width hw0, z from zt0 (top) to zb0,
 * at x1 hw1, zt1, zb1; centred on y = yc. */
static void taper_box(const scn *d, int fr, double x0, double x1, double yc, double hw0, double hw1, double zt0,
                      double zb0, double zt1, double zb1)
{
    double c[8][3];
    for (int k = 0; k < 8; k++) {
        int fx = k & 1, fy = (k >> 1) & 1, fz = (k >> 2) & 1;
        double hw = fx ? hw1 : hw0;
        c[k][0] = fx ? x1 : x0;
        c[k][1] = yc + (fy ? hw : -hw);
        c[k][2] = fz ? (fx ? zb1 : zb0) : (fx ? zt1 : zt0);
    }
    hexa(d, fr, c);
}

/* A box about centre ctr with half-extents h along unit axes a0, a1, a2. */
static void obox(const scn *d, int fr, const double ctr[3], const double a0[3], const double a1[3],
                 const double a2[3], const double h[3])
{
    double c[8][3];
    for (int k = 0; k < 8; k++) {
        double s0 = (k & 1) ? 1 : -1, s1 = ((k >> 1) & 1) ? 1 : -1, s2 = ((k >> 2) & 1) ? 1 : -1;
        for (int i = 0; i < 3; i++)
            c[k][i] = ctr[i] + s0 * h[0] * a0[i] + s1 * h[1] * a1[i] + s2 * h[2] * a2[i];
    }
    hexa(d, fr, c);
}

/* Two unit vectors spanning the plane normal to unit n. */
static void plane_axes(const double n[3], double u[3], double w[3])
{
    double h[3] = {1, 0, 0};
    if (fabs(n[0]) > 0.8)
        h[0] = 0, h[1] = 1;
    cross3(n, h, u);
    unit3(u);
    cross3(n, u, w);
}

/* An annulus (r0 = 0: a disk) about c in the plane normal to unit n. */
static void ring(const scn *d, int fr, const double c[3], const double n[3], double r0, double r1, int segs)
{
    double u[3], w[3];
    plane_axes(n, u, w);
    nrm(d, fr, n);
    glBegin(GL_TRIANGLE_STRIP);
    for (int k = 0; k <= segs; k++) {
        double a = 2.0 * CORE_PI * k / segs, ca = cos(a), sa = sin(a), p[3], q[3];
        for (int i = 0; i < 3; i++) {
            p[i] = c[i] + r1 * (ca * u[i] + sa * w[i]);
            q[i] = c[i] + r0 * (ca * u[i] + sa * w[i]);
        }
        vtx(d, fr, p);
        vtx(d, fr, q);
    }
    glEnd();
}

/* A closed cylinder about c, axis unit a, radius r, half-length hl. */
static void cylinder(const scn *d, int fr, const double c[3], const double a[3], double r, double hl, int segs)
{
    double u[3], w[3];
    plane_axes(a, u, w);
    glBegin(GL_QUAD_STRIP);
    for (int k = 0; k <= segs; k++) {
        double t = 2.0 * CORE_PI * k / segs, rad[3], p[3], q[3];
        for (int i = 0; i < 3; i++) {
            rad[i] = cos(t) * u[i] + sin(t) * w[i];
            p[i] = c[i] + r * rad[i] + hl * a[i];
            q[i] = c[i] + r * rad[i] - hl * a[i];
        }
        nrm(d, fr, rad);
        vtx(d, fr, p);
        vtx(d, fr, q);
    }
    glEnd();
    for (int e = -1; e <= 1; e += 2) {
        double ce[3] = {c[0] + e * hl * a[0], c[1] + e * hl * a[1], c[2] + e * hl * a[2]};
        double ne[3] = {e * a[0], e * a[1], e * a[2]};
        ring(d, fr, ce, ne, 0.0, r, segs);
    }
}

/* ------------------------------------------------------------------ sky */
static void draw_sky(const scn *d, const render_view *v)
{
    static const double el_deg[] = {-90, -2, 0, 2, 5, 10, 18, 30, 45, 62, 78, 90};
    enum { NEL = sizeof el_deg / sizeof el_deg[0], NAZ = 36 };
    const uint8_t *hz = colour_table[RENDER_COLOUR_SKY_HORIZON], *zn = colour_table[RENDER_COLOUR_SKY_ZENITH];
    double col[NEL][3];
    for (int k = 0; k < NEL; k++) {
        double t = el_deg[k] > 0 ? pow(sin(el_deg[k] * CORE_DEG_TO_RAD), 0.6) : 0.0;
        for (int i = 0; i < 3; i++)
            col[k][i] = (hz[i] + t * (zn[i] - hz[i])) / 255.0;
    }
    for (int k = 0; k + 1 < NEL; k++) {
        glBegin(GL_QUAD_STRIP);
        for (int a = 0; a <= NAZ; a++) {
            double az = 2.0 * CORE_PI * a / NAZ;
            for (int j = 1; j >= 0; j--) {
                double el = el_deg[k + j] * CORE_DEG_TO_RAD, p[3];
                p[0] = v->eye_E_m[0] + SKY_R_M * cos(el) * cos(az);
                p[1] = v->eye_E_m[1] + SKY_R_M * cos(el) * sin(az);
                p[2] = v->eye_E_m[2] - SKY_R_M * sin(el);
                glColor3dv(col[k + j]);
                render_gl_vertex_E(d->rc, p);
            }
        }
        glEnd();
    }
}

/* ------------------------------------------------------------------ sea */
static int draw_sea(const scn *d, core_err *err)
{
    const render_scene *sc = d->sc;
    const int n = SEA_N * SEA_N;
    const double dx = SEA_SIDE_M / (SEA_N - 1), half = 0.5 * SEA_SIDE_M, z0 = sc->ship->deck_height_m;
    double cx = dx * floor(d->s->ship.pos_E_m.x / dx + 0.5), cy = dx * floor(d->s->ship.pos_E_m.y / dx + 0.5);
    double *buf = malloc(sizeof *buf * 3 * (size_t)n);
    if (!buf)
        return core_err_set(err, -1, "render: out of memory (sea grid)");
    double *x = buf, *y = buf + n, *eta = buf + 2 * n;
    for (int j = 0; j < SEA_N; j++)
        for (int i = 0; i < SEA_N; i++) {
            x[j * SEA_N + i] = cx + (-half + dx * i);
            y[j * SEA_N + i] = cy + (-half + dx * j);
        }
    int flat = 1;
    if (sc->sea) {
        int r = sc->sea(sc->sea_user, d->s->t_s, n, x, y, eta);
        flat = r < 0;
        for (int k = 0; !flat && k < n; k++)
            if (!isfinite(eta[k])) {
                double xk = x[k], yk = y[k];
                free(buf);
                return core_err_set(err, -1, "render: the sea elevation at (%g, %g) m (E) at t = %g s is not "
                                    "finite", xk, yk, d->s->t_s);
            }
    }
    if (flat)
        memset(eta, 0, sizeof *eta * (size_t)n);
    /* Taper to the mean level over the outer tenth (the flat far sea
     * meets the grid's edge without a step). */
    for (int j = 0; j < SEA_N; j++)
        for (int i = 0; i < SEA_N; i++) {
            double r = fmax(fabs(i - 0.5 * (SEA_N - 1)), fabs(j - 0.5 * (SEA_N - 1))) / (0.5 * (SEA_N - 1));
            double w = r < 0.9 ? 1.0 : 0.5 + 0.5 * cos(CORE_PI * (r - 0.9) / 0.1);
            eta[j * SEA_N + i] *= w;
        }
    colour(RENDER_COLOUR_SEA, 1.0, 1.0);
    for (int j = 0; j + 1 < SEA_N; j++) {
        glBegin(GL_TRIANGLE_STRIP);
        for (int i = 0; i < SEA_N; i++)
            for (int jj = j + 1; jj >= j; jj--) {
                int k = jj * SEA_N + i;
                int im = i > 0 ? i - 1 : i, ip = i + 1 < SEA_N ? i + 1 : i;
                int jm = jj > 0 ? jj - 1 : jj, jp = jj + 1 < SEA_N ? jj + 1 : jj;
                double gx = (eta[jj * SEA_N + ip] - eta[jj * SEA_N + im]) / (dx * (ip - im));
                double gy = (eta[jp * SEA_N + i] - eta[jm * SEA_N + i]) / (dx * (jp - jm));
                double nn[3] = {-gx, -gy, -1.0}, p[3] = {x[k], y[k], z0 - eta[k]};
                unit3(nn);
                render_gl_normal_E(nn);
                render_gl_vertex_E(d->rc, p);
            }
        glEnd();
    }
    /* The flat far sea: square rings from the grid's edge outward, each
     * 1.42 times the last: the haze is evaluated at the vertices, so one
     * large quad with every corner kilometres away would come out haze
     * from edge to edge. Each side has the grid's SEA_N - 1 segments, so
     * the first ring meets the grid vertex to vertex (a T-junction there
     * leaves pixel cracks that show the sky). */
    static const double ring_m[] = {0.5 * SEA_SIDE_M, 560, 800, 1150, 1650, 2400, 3400, 4900, SEA_FAR_M};
    enum { NR = sizeof ring_m / sizeof ring_m[0], NSEG = 4 * (SEA_N - 1) };
    double up[3] = {0, 0, -1};
    render_gl_normal_E(up);
    for (int r = 0; r + 1 < NR; r++) {
        glBegin(GL_QUAD_STRIP);
        for (int k = 0; k <= NSEG; k++) {
            /* perimeter parameter: 4 sides of NSEG / 4 segments */
            int side = (k / (NSEG / 4)) % 4;
            int i = k % (NSEG / 4);
            if (k == NSEG)
                side = 0, i = 0;
            for (int j = 1; j >= 0; j--) {
                /* As the grid's vertices: -hr + step i (exactly, on the
                 * grid's edge). */
                double hr = ring_m[r + j], st = 2.0 * hr / (SEA_N - 1), p[3];
                double a = -hr + st * i, b = -hr + st * (SEA_N - 1 - i);
                double px_ = side == 0 ? a : side == 1 ? hr : side == 2 ? b : -hr;
                double py_ = side == 0 ? -hr : side == 1 ? a : side == 2 ? hr : b;
                p[0] = cx + px_, p[1] = cy + py_, p[2] = z0;
                render_gl_vertex_E(d->rc, p);
            }
        }
        glEnd();
    }
    free(buf);
    return 0;
}

/* ----------------------------------------------------------------- ship */
static void draw_block(const scn *d, const core_ship_block *b)
{
    double yc = 0.5 * (b->y0_m + b->y1_m), hw = 0.5 * (b->y1_m - b->y0_m);
    double xt = b->bow_taper_m > 0.0 ? fmax(b->x0_m, b->x1_m - b->bow_taper_m) : b->x1_m;
    if (xt > b->x0_m)
        taper_box(d, FR_S, b->x0_m, xt, yc, hw, hw, b->z0_m, b->z1_m, b->z0_m, b->z1_m);
    if (b->x1_m > xt)
        taper_box(d, FR_S, xt, b->x1_m, yc, hw, 0.0, b->z0_m, b->z1_m, b->z0_m, b->z1_m);
}

/* A deck rectangle (x, y ranges in S) at z_S just above the deck. */
static void deck_rect(const scn *d, double x0, double x1, double y0, double y1, double z)
{
    glBegin(GL_QUADS);
    vtx3(d, FR_S, x0, y0, z);
    vtx3(d, FR_S, x1, y0, z);
    vtx3(d, FR_S, x1, y1, z);
    vtx3(d, FR_S, x0, y1, z);
    glEnd();
}

/* The hangar: the block rising from the deck's forward end across the
 * centre line (the nearest one to deck_x1_m); NULL if none. */
static const core_ship_block *find_hangar(const core_ship *sh)
{
    const core_ship_block *best = NULL;
    for (int i = 0; i < sh->nblocks; i++) {
        const core_ship_block *b = &sh->blocks[i];
        if (b->z0_m < -1.0 && b->y0_m < 0.0 && b->y1_m > 0.0 && fabs(b->x0_m - sh->deck_x1_m) < 2.0 &&
            (!best || fabs(b->x0_m - sh->deck_x1_m) < fabs(best->x0_m - sh->deck_x1_m)))
            best = b;
    }
    return best;
}

static void draw_ship(const scn *d)
{
    const core_ship *sh = d->sc->ship;
    double up_S[3] = {0, 0, -1};
    colour(RENDER_COLOUR_HULL, 1.0, 1.0);
    for (int i = 0; i < sh->nblocks; i++)
        draw_block(d, &sh->blocks[i]);

    /* Decals on the deck: each layer a little higher and pulled toward the
     * eye by a polygon offset, so none fights the deck for depth. */
    double x0 = sh->deck_x0_m, x1 = sh->deck_x1_m, hw = sh->deck_halfwidth_m;
    glEnable(GL_POLYGON_OFFSET_FILL);
    nrm(d, FR_S, up_S);
    glPolygonOffset(-1.0f, -2.0f);
    colour(RENDER_COLOUR_DECK, 1.0, 1.0);
    deck_rect(d, x0, x1, -hw, hw, -0.01);
    glPolygonOffset(-1.0f, -4.0f);
    colour(RENDER_COLOUR_MARKING, 1.0, 1.0);
    deck_rect(d, x0, x1, -0.15, 0.15, -0.02);             /* line-up line, aft edge to the hangar */
    deck_rect(d, x0, x1, hw - 0.35, hw - 0.15, -0.02);    /* deck-edge lines */
    deck_rect(d, x0, x1, -hw + 0.15, -hw + 0.35, -0.02);
    deck_rect(d, x0 + 0.15, x0 + 0.35, -hw + 0.15, hw - 0.15, -0.02);
    glPolygonOffset(-1.0f, -6.0f);
    colour(RENDER_COLOUR_SPOT, 1.0, 1.0);
    double rc_m = fmin(0.4 * hw, 3.0), o_S[3] = {0, 0, -0.03}, n_S[3] = {0, 0, -1};
    ring(d, FR_S, o_S, n_S, rc_m - 0.3, rc_m, 64); /* the landing circle */
    ring(d, FR_S, o_S, n_S, 0.0, 0.5, 24);         /* the spot at its centre */
    glDisable(GL_POLYGON_OFFSET_FILL);

    const core_ship_block *hg = find_hangar(sh);
    if (hg) {
        /* The door: a darker panel on the hangar face, from the deck up to
         * 0.7 of the face's height, 0.6 of its width. */
        double xf = hg->x0_m - 0.03, yc = 0.5 * (hg->y0_m + hg->y1_m), dw = 0.3 * (hg->y1_m - hg->y0_m);
        double aft_S[3] = {-1, 0, 0};
        colour(RENDER_COLOUR_HULL, 0.72, 1.0);
        glBegin(GL_QUADS);
        nrm(d, FR_S, aft_S);
        vtx3(d, FR_S, xf, yc - dw, 0.0);
        vtx3(d, FR_S, xf, yc + dw, 0.0);
        vtx3(d, FR_S, xf, yc + dw, 0.7 * hg->z0_m);
        vtx3(d, FR_S, xf, yc - dw, 0.7 * hg->z0_m);
        glEnd();
    }

    glDisable(GL_LIGHTING);
    /* Deck-edge lights: small bright boxes along both edges about 3 m apart. */
    colour(RENDER_COLOUR_LIGHT, 1.0, 1.0);
    int nl = (int)floor((x1 - x0) / 3.0) + 1;
    double ax[3] = {1, 0, 0}, ay[3] = {0, 1, 0}, az[3] = {0, 0, 1}, lh[3] = {0.15, 0.15, 0.06};
    for (int k = 0; k < nl; k++) {
        double xk = nl > 1 ? x0 + 0.3 + (x1 - x0 - 0.6) * k / (nl - 1) : 0.5 * (x0 + x1);
        for (int side = -1; side <= 1; side += 2) {
            double c[3] = {xk, side * (hw - 0.05), -0.06};
            obox(d, FR_S, c, ax, ay, az, lh);
        }
    }
    if (hg) {
        /* The horizon bar: level in E whatever the ship's roll and pitch,
         * along the horizontal normal to the ship's heading, centred 0.35 m
         * above the hangar face's top edge and 0.08 m aft of it, half the
         * hangar's width long (at most 6 m), 0.3 m tall. */
        double c_S[3] = {hg->x0_m - 0.08, 0.5 * (hg->y0_m + hg->y1_m), hg->z0_m - 0.35}, c[3];
        double xs[3] = {1, 0, 0}, xe[3], down[3] = {0, 0, 1}, bar[3], aft[3];
        to_E(d, FR_S, c_S, c);
        vec_E(d, FR_S, xs, xe);
        cross3(down, xe, bar);
        if (unit3(bar) == 0) {
            cross3(bar, down, aft); /* horizontal, along the bow */
            double hl[3] = {fmin(0.25 * (hg->y1_m - hg->y0_m), 3.0), 0.15, 0.05};
            colour(RENDER_COLOUR_HORIZON_BAR, 1.0, 1.0);
            obox(d, FR_E, c, bar, down, aft, hl);
        }
    }
    glEnable(GL_LIGHTING);
}

/* ----------------------------------------------------------- helicopter */
typedef struct heli_dims {
    double R, nose_x, belly_z, roof_z, cab_hw, cab_x0, nose_x0;
    double boom_x0, boom_x1, boom_z0, boom_z1, boom_h0, boom_h1, boom_hw0, boom_hw1;
} heli_dims;

static int strike_point(const hfm_geometry *g, const char *name, double p[3])
{
    for (int i = 0; i < g->gear.npoints && i < HFM_GEAR_MAX_POINTS; i++)
        if (strcmp(g->gear.point_name[i], name) == 0) {
            memcpy(p, g->gear.point_B_m[i], 3 * sizeof *p);
            return 1;
        }
    return 0;
}

static void heli_dims_of(const hfm_geometry *g, heli_dims *h)
{
    double R = g->rotor_radius_m, p[3];
    h->R = R;
    h->nose_x = strike_point(g, "nose", p) ? p[0] : 0.62 * R;
    h->belly_z = strike_point(g, "belly", p) ? p[2] : g->hub_B_m[2] + 0.40 * R;
    h->roof_z = g->hub_B_m[2] + 0.09 * R;
    if (h->belly_z < h->roof_z + 0.5)
        h->belly_z = h->roof_z + 0.5;
    h->cab_hw = 0.13 * R;
    h->cab_x0 = g->hub_B_m[0] - 0.35 * R;
    h->nose_x0 = h->nose_x - 0.15 * R;
    if (h->nose_x0 < h->cab_x0 + 0.5)
        h->nose_x0 = h->cab_x0 + 0.5;
    double ch = h->belly_z - h->roof_z;
    h->boom_x0 = h->cab_x0 + 0.3;
    h->boom_x1 = g->tail_hub_B_m[0];
    h->boom_z0 = h->roof_z + 0.35 * ch;
    h->boom_z1 = g->stab_B_m[0] < h->cab_x0 ? g->stab_B_m[2] : g->tail_hub_B_m[2] + 0.5;
    h->boom_h0 = 0.12 * R;
    h->boom_h1 = 0.05 * R;
    h->boom_hw0 = 0.07 * R;
    h->boom_hw1 = 0.03 * R;
}

/* The boom's underside at body x (for the gear's struts). */
static double boom_bottom(const heli_dims *h, double x)
{
    double t = (h->boom_x0 - x) / (h->boom_x0 - h->boom_x1);
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    return h->boom_z0 + t * (h->boom_z1 - h->boom_z0) + 0.5 * (h->boom_h0 + t * (h->boom_h1 - h->boom_h0));
}

/* Rotor blades: nb flat blades from r0 to r1 of chord ch in the plane of
 * (e1, e2) about c, blade 1 at azimuth az from -e1 (aft), turning toward
 * +e2 when dir is +1 (counter-clockwise seen from the -n side's above). */
static void blades(const scn *d, const double c[3], const double e1[3], const double e2[3], const double n[3],
                   int nb, double az, int dir, double r0, double r1, double ch)
{
    nrm(d, FR_B, n);
    glBegin(GL_QUADS);
    for (int k = 0; k < nb; k++) {
        double a = az + 2.0 * CORE_PI * k / nb, ca = -cos(a), sa = dir * sin(a), sp[3], tg[3];
        for (int i = 0; i < 3; i++) {
            sp[i] = ca * e1[i] + sa * e2[i];
            tg[i] = -sa * e1[i] + ca * e2[i];
        }
        double q[4][3];
        for (int i = 0; i < 3; i++) {
            q[0][i] = c[i] + r0 * sp[i] - 0.5 * ch * tg[i];
            q[1][i] = c[i] + r1 * sp[i] - 0.5 * ch * tg[i];
            q[2][i] = c[i] + r1 * sp[i] + 0.5 * ch * tg[i];
            q[3][i] = c[i] + r0 * sp[i] + 0.5 * ch * tg[i];
        }
        for (int j = 0; j < 4; j++)
            vtx(d, FR_B, q[j]);
    }
    glEnd();
}

/* The main rotor's disk axes in B: e1 forward, e2 right in the tilted
 * plane, n its normal up the shaft. */
static void main_rotor_axes(const hfm_geometry *g, double e1[3], double e2[3], double n[3])
{
    double st = sin(g->shaft_tilt_rad), ct = cos(g->shaft_tilt_rad);
    e1[0] = ct, e1[1] = 0, e1[2] = st;
    e2[0] = 0, e2[1] = 1, e2[2] = 0;
    n[0] = st, n[1] = 0, n[2] = -ct;
}

static void tail_axes(const hfm_geometry *g, double n[3], double e1[3], double e2[3])
{
    memcpy(n, g->tail_dir_B, 3 * sizeof *n);
    if (unit3(n) != 0)
        n[0] = 0, n[1] = 1, n[2] = 0;
    /* e1 in the disk along -x_B as far as it can (blade azimuth 0 aft). */
    double ax[3] = {1, 0, 0}, d = dot3(ax, n);
    for (int i = 0; i < 3; i++)
        e1[i] = ax[i] - d * n[i];
    if (unit3(e1) != 0)
        e1[0] = 0, e1[1] = 0, e1[2] = 1;
    cross3(n, e1, e2);
}

/* The cockpit's frame as the pilot sees it from inside: the windscreen's
 * posts and the instrument panel's coaming, a little ahead of the eye. */
static void draw_cockpit(const scn *d, const heli_dims *h, const double eye_B[3])
{
    double ax[3] = {1, 0, 0}, ay[3] = {0, 1, 0}, az[3] = {0, 0, 1};
    double xw = eye_B[0] + 0.6, ch = h->belly_z - h->roof_z, zc = eye_B[2] + 0.5;
    colour(RENDER_COLOUR_FUSELAGE, 0.55, 1.0);
    /* The coaming: a shelf across the cabin 0.5 m under the eye, 0.6 m
     * ahead (the view over it reaches about 40 deg down). */
    double cc[3] = {xw + 0.2, 0.0, zc + 0.05}, chh[3] = {0.2, h->cab_hw, 0.05};
    obox(d, FR_B, cc, ax, ay, az, chh);
    /* Posts: the centre one and one each side, from the coaming to the roof. */
    for (int k = -1; k <= 1; k++) {
        double pc[3] = {xw, k * 0.9 * h->cab_hw, 0.5 * (zc + h->roof_z)};
        double ph[3] = {0.04, k ? 0.06 : 0.03, 0.5 * (zc - h->roof_z)};
        obox(d, FR_B, pc, ax, ay, az, ph);
    }
    /* The roof's front edge. */
    double rc[3] = {xw, 0.0, h->roof_z + 0.02 * ch}, rh[3] = {0.05, h->cab_hw, 0.04};
    obox(d, FR_B, rc, ax, ay, az, rh);
}

static void draw_heli_solid(const scn *d, const render_view *v)
{
    const hfm_geometry *g = d->sc->heli;
    heli_dims h;
    heli_dims_of(g, &h);
    double R = h.R, ch = h.belly_z - h.roof_z;
    double ax[3] = {1, 0, 0}, ay[3] = {0, 1, 0}, az[3] = {0, 0, 1};
    /* An eye inside the cabin (the pilot's) sees the cockpit's frame, not
     * the cabin's walls from inside. */
    double rel[3], eb[3];
    for (int i = 0; i < 3; i++)
        rel[i] = v->eye_E_m[i] - d->t[FR_B][i];
    for (int c = 0; c < 3; c++)
        eb[c] = d->R[FR_B][0][c] * rel[0] + d->R[FR_B][1][c] * rel[1] + d->R[FR_B][2][c] * rel[2];
    int inside = eb[0] > h.cab_x0 - 0.2 && eb[0] < h.nose_x + 0.2 && fabs(eb[1]) < h.cab_hw + 0.2 &&
                 eb[2] > h.roof_z - 0.2 && eb[2] < h.belly_z + 0.2;

    colour(RENDER_COLOUR_FUSELAGE, 1.0, 1.0);
    double fz = g->hub_B_m[2] + 0.035 * R;
    if (inside) {
        draw_cockpit(d, &h, eb);
    } else {
        /* Cabin and tapered nose. */
        taper_box(d, FR_B, h.cab_x0, h.nose_x0, 0.0, h.cab_hw, h.cab_hw, h.roof_z, h.belly_z, h.roof_z, h.belly_z);
        taper_box(d, FR_B, h.nose_x0, h.nose_x, 0.0, h.cab_hw, 0.55 * h.cab_hw, h.roof_z, h.belly_z,
                  h.roof_z + 0.45 * ch, h.belly_z - 0.12 * ch);
        /* Engine and transmission fairing under the hub. */
        taper_box(d, FR_B, g->hub_B_m[0] - 0.22 * R, g->hub_B_m[0] + 0.12 * R, 0.0, 0.7 * h.cab_hw,
                  0.5 * h.cab_hw, fz, h.roof_z + 0.05, fz + 0.03 * R, h.roof_z + 0.05);
    }
    colour(RENDER_COLOUR_FUSELAGE, 1.0, 1.0);
    /* The cabin's aft fairing, tapering 0.15 R into the boom. */
    taper_box(d, FR_B, h.cab_x0 - 0.15 * R, h.cab_x0, 0.0, h.boom_hw0, h.cab_hw, h.boom_z0 - 0.5 * h.boom_h0,
              h.boom_z0 + 0.5 * h.boom_h0, h.roof_z, h.belly_z - 0.3 * ch);
    /* Tail boom. */
    taper_box(d, FR_B, h.boom_x1, h.boom_x0, 0.0, h.boom_hw1, h.boom_hw0, h.boom_z1 - 0.5 * h.boom_h1,
              h.boom_z1 + 0.5 * h.boom_h1, h.boom_z0 - 0.5 * h.boom_h0, h.boom_z0 + 0.5 * h.boom_h0);
    /* Horizontal stabiliser (span 0.54 R, chord 0.1 R) where the file has one. */
    if (g->stab_B_m[0] < h.cab_x0) {
        double hs[3] = {0.05 * R, 0.27 * R, 0.04};
        obox(d, FR_B, g->stab_B_m, ax, ay, az, hs);
    }
    const double *th = g->tail_hub_B_m;
    double tr = g->tail_radius_m > 0 ? g->tail_radius_m : 0.1 * R;
    double n[3], e1[3], e2[3];
    tail_axes(g, n, e1, e2);
    if (g->tail_fenestron) {
        /* A fin around the fan: a plate in the body's x-z plane. */
        double fx0 = th[0] - 1.8 * tr, fx1 = th[0] + 1.8 * tr, ft = 0.35 * tr;
        taper_box(d, FR_B, fx0, fx1, th[1], ft, ft, th[2] - 3.0 * tr, th[2] + 1.5 * tr, th[2] - 1.4 * tr,
                  h.boom_z1 + 0.5 * h.boom_h1);
        /* The duct: a lighter ring and the dark fan, proud of both faces. */
        for (int side = -1; side <= 1; side += 2) {
            double c[3], ns[3];
            for (int i = 0; i < 3; i++) {
                c[i] = th[i] + side * (ft + 0.01) * n[i];
                ns[i] = side * n[i];
            }
            colour(RENDER_COLOUR_HULL, 0.8, 1.0);
            ring(d, FR_B, c, ns, tr, 1.25 * tr, 32);
            colour(RENDER_COLOUR_ROTOR, 1.0, 1.0);
            ring(d, FR_B, c, ns, 0.0, tr, 32);
            colour(RENDER_COLOUR_FUSELAGE, 1.0, 1.0);
        }
    } else {
        /* A swept fin from the boom's end up past the tail rotor's hub. */
        double top = fmin(th[2], g->fin_B_m[2]) - 0.6 * tr, bot = h.boom_z1 + 0.5 * h.boom_h1;
        double c[8][3], ft = 0.08;
        for (int k = 0; k < 8; k++) {
            int fx = k & 1, fy = (k >> 1) & 1, fz = (k >> 2) & 1;
            c[k][0] = fz ? (fx ? th[0] + 0.12 * R : th[0] - 0.04 * R) : (fx ? th[0] + 0.02 * R : th[0] - 0.06 * R);
            c[k][1] = fy ? ft : -ft;
            c[k][2] = fz ? bot : top;
        }
        hexa(d, FR_B, c);
        /* The tail rotor's blades (the disk is drawn with the translucent ones). */
        double ratio = g->rotor_omega_radps > 0 ? g->tail_omega_radps / g->rotor_omega_radps : 4.0;
        colour(RENDER_COLOUR_ROTOR, 1.0, 1.0);
        blades(d, th, e1, e2, n, g->tail_blades > 0 ? g->tail_blades : 2, d->s->rotor_azimuth_rad * ratio, 1,
               0.1 * tr, tr, 0.18 * tr);
        double hubh[3] = {0.12 * tr, 0.12 * tr, 0.12 * tr};
        obox(d, FR_B, th, e1, e2, n, hubh);
    }
    /* Mast, hub and blades. */
    double me1[3], me2[3], mn[3];
    main_rotor_axes(g, me1, me2, mn);
    colour(RENDER_COLOUR_ROTOR, 1.0, 1.0);
    double hub_c[3], mast_c[3];
    for (int i = 0; i < 3; i++) {
        hub_c[i] = g->hub_B_m[i];
        mast_c[i] = g->hub_B_m[i] - 0.5 * 0.04 * R * mn[i];
    }
    double mh[3] = {0.1, 0.1, 0.02 * R + 0.05};
    obox(d, FR_B, mast_c, me1, me2, mn, mh);
    cylinder(d, FR_B, hub_c, mn, 0.06 * R, 0.15, 16);
    blades(d, hub_c, me1, me2, mn, g->blades > 0 ? g->blades : 2, d->s->rotor_azimuth_rad, g->rotor_ccw ? 1 : -1,
           0.06 * R, R, 0.065 * R);
    /* Gear: struts up to the structure, wheels with axles along body y. */
    for (int k = 0; k < g->gear.nlegs && k < HFM_GEAR_MAX_LEGS; k++) {
        const hfm_gear_leg *L = &g->gear.leg[k];
        const double *w = L->pos_B_m;
        double top = (w[0] >= h.cab_x0 && w[0] <= h.nose_x) ? h.belly_z - 0.1 : boom_bottom(&h, w[0]) - 0.05;
        if (top > w[2] - 0.2)
            top = w[2] - 0.2;
        double sc_[3] = {w[0], w[1], 0.5 * (top + w[2])}, sh_[3] = {0.06, 0.06, 0.5 * (w[2] - top)};
        colour(RENDER_COLOUR_FUSELAGE, 0.8, 1.0);
        obox(d, FR_B, sc_, ax, ay, az, sh_);
        double tyre = L->tyre_radius_m > 0 ? L->tyre_radius_m : 0.2;
        colour(RENDER_COLOUR_ROTOR, 1.0, 1.0);
        cylinder(d, FR_B, w, ay, tyre, 0.4 * tyre, 16);
    }
}

static void draw_heli_disks(const scn *d)
{
    const hfm_geometry *g = d->sc->heli;
    double e1[3], e2[3], n[3], c[3];
    main_rotor_axes(g, e1, e2, n);
    /* Just under the blades, so a blade never ties with the disk. */
    for (int i = 0; i < 3; i++)
        c[i] = g->hub_B_m[i] - 0.03 * n[i];
    colour(RENDER_COLOUR_ROTOR, 1.0, 0.28);
    ring(d, FR_B, c, n, 0.0, g->rotor_radius_m, 72);
    if (!g->tail_fenestron && g->tail_radius_m > 0) {
        double tn[3], t1[3], t2[3];
        tail_axes(g, tn, t1, t2);
        ring(d, FR_B, g->tail_hub_B_m, tn, 0.0, g->tail_radius_m, 32);
    }
}

/* --------------------------------------------------------------- frame */
static int finite_pose(const core_pose *p)
{
    return isfinite(p->pos_E_m.x) && isfinite(p->pos_E_m.y) && isfinite(p->pos_E_m.z) && isfinite(p->q_EF.w) &&
           isfinite(p->q_EF.x) && isfinite(p->q_EF.y) && isfinite(p->q_EF.z) &&
           fabs(p->q_EF.w * p->q_EF.w + p->q_EF.x * p->q_EF.x + p->q_EF.y * p->q_EF.y + p->q_EF.z * p->q_EF.z -
                1.0) < 1e-6;
}

int render_frame_gl(render_ctx *rc, const render_scene *sc, const render_state *s, const render_view *v,
                    core_err *err)
{
    if (!rc || !sc || !sc->ship || !s)
        return core_err_set(err, -1, "render: frame: expected a context, a scene with a ship and a state");
    if (render_view_check(v, err) < 0)
        return -1;
    if (!finite_pose(&s->ship))
        return core_err_set(err, -1, "render: state at t = %g s: the ship's pose is not finite with a unit "
                            "quaternion", s->t_s);
    int heli = s->have_heli && sc->heli;
    if (heli && !finite_pose(&s->heli))
        return core_err_set(err, -1, "render: state at t = %g s: the helicopter's pose is not finite with a "
                            "unit quaternion", s->t_s);
    if (!OSMesaMakeCurrent(rc->gl, rc->buf, GL_UNSIGNED_BYTE, rc->w, rc->h))
        return core_err_set(err, -1, "render: OSMesaMakeCurrent failed");

    scn d = {.rc = rc, .sc = sc, .s = s};
    for (int i = 0; i < 3; i++)
        d.R[FR_E][i][i] = 1.0;
    quat_to_R(s->ship.q_EF, d.R[FR_S]);
    d.t[FR_S][0] = s->ship.pos_E_m.x, d.t[FR_S][1] = s->ship.pos_E_m.y, d.t[FR_S][2] = s->ship.pos_E_m.z;
    if (heli) {
        quat_to_R(s->heli.q_EF, d.R[FR_B]);
        d.t[FR_B][0] = s->heli.pos_E_m.x, d.t[FR_B][1] = s->heli.pos_E_m.y, d.t[FR_B][2] = s->heli.pos_E_m.z;
    }
    memcpy(rc->origin_E_m, d.t[FR_S], sizeof rc->origin_E_m);

    double proj[16], mv[16];
    render_gl_matrices(v, rc->w, rc->h, rc->origin_E_m, proj, mv);
    glViewport(0, 0, rc->w, rc->h);
    glDisable(GL_DITHER);
    glDisable(GL_CULL_FACE);
    glDisable(GL_BLEND);
    glShadeModel(GL_SMOOTH);
    const uint8_t *hz = colour_table[RENDER_COLOUR_SKY_HORIZON];
    glClearColor(hz[0] / 255.0f, hz[1] / 255.0f, hz[2] / 255.0f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glMatrixMode(GL_PROJECTION);
    glLoadMatrixd(proj);
    glMatrixMode(GL_MODELVIEW);
    glLoadMatrixd(mv);

    /* The sky first, behind everything: no depth, no light, no haze. */
    glDisable(GL_DEPTH_TEST);
    glDepthMask(GL_FALSE);
    glDisable(GL_LIGHTING);
    glDisable(GL_FOG);
    draw_sky(&d, v);
    glDepthMask(GL_TRUE);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);

    /* The sun (w = 0: a direction, fixed in E; GL applies the model-view
     * loaded above to it). */
    double el = SUN_EL_DEG * CORE_DEG_TO_RAD, azr = SUN_AZ_DEG * CORE_DEG_TO_RAD;
    double sun_E[3] = {cos(el) * cos(azr), cos(el) * sin(azr), -sin(el)};
    GLfloat sun[4] = {(GLfloat)sun_E[0], (GLfloat)-sun_E[2], (GLfloat)sun_E[1], 0.0f};
    GLfloat dif[4] = {SCN_DIFFUSE, SCN_DIFFUSE, SCN_DIFFUSE, 1.0f}, zero[4] = {0, 0, 0, 1};
    GLfloat amb[4] = {SCN_AMBIENT, SCN_AMBIENT, SCN_AMBIENT, 1.0f};
    glEnable(GL_LIGHTING);
    glEnable(GL_LIGHT0);
    glLightfv(GL_LIGHT0, GL_POSITION, sun);
    glLightfv(GL_LIGHT0, GL_DIFFUSE, dif);
    glLightfv(GL_LIGHT0, GL_AMBIENT, zero);
    glLightfv(GL_LIGHT0, GL_SPECULAR, zero);
    glLightModelfv(GL_LIGHT_MODEL_AMBIENT, amb);
    glLightModeli(GL_LIGHT_MODEL_TWO_SIDE, GL_FALSE);
    glEnable(GL_COLOR_MATERIAL);
    glColorMaterial(GL_FRONT_AND_BACK, GL_AMBIENT_AND_DIFFUSE);
    glEnable(GL_NORMALIZE);
    GLfloat fogc[4] = {hz[0] / 255.0f, hz[1] / 255.0f, hz[2] / 255.0f, 1.0f};
    glEnable(GL_FOG);
    glFogi(GL_FOG_MODE, GL_EXP2);
    glFogf(GL_FOG_DENSITY, (GLfloat)FOG_DENSITY_PER_M);
    glFogfv(GL_FOG_COLOR, fogc);
    glHint(GL_FOG_HINT, GL_NICEST);

    if (draw_sea(&d, err) < 0)
        return -1;
    draw_ship(&d);
    if (heli)
        draw_heli_solid(&d, v);

    if ((sc->overlays & RENDER_OVERLAY_AIRWAKE) && sc->air) {
        if (render_overlay_airwake(rc, sc, s, err) < 0)
            return -1;
        /* The overlay may leave its own state: the disks want ours. */
        glMatrixMode(GL_PROJECTION);
        glLoadMatrixd(proj);
        glMatrixMode(GL_MODELVIEW);
        glLoadMatrixd(mv);
        glEnable(GL_DEPTH_TEST);
        glEnable(GL_LIGHTING);
        glEnable(GL_FOG);
        glEnable(GL_COLOR_MATERIAL);
        glDisable(GL_TEXTURE_2D);
    }
    if (heli) {
        glEnable(GL_BLEND);
        glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
        glDepthMask(GL_FALSE);
        draw_heli_disks(&d);
        glDepthMask(GL_TRUE);
        glDisable(GL_BLEND);
    }
    GLenum ge = glGetError();
    if (ge != GL_NO_ERROR)
        return core_err_set(err, -1, "render: OpenGL error 0x%x", (unsigned)ge);
    return 0;
}

void render_read_back(const render_ctx *rc, uint8_t *rgba)
{
    glFinish();
    /* GL's rows run bottom up; the image is opaque. */
    size_t row = (size_t)4 * rc->w;
    for (int y = 0; y < rc->h; y++) {
        uint8_t *o = rgba + (size_t)y * row;
        memcpy(o, rc->buf + (size_t)(rc->h - 1 - y) * row, row);
        for (int x = 0; x < rc->w; x++)
            o[4 * x + 3] = 255;
    }
}

int render_frame(render_ctx *rc, const render_scene *sc, const render_state *s, const render_view *v,
                 uint8_t *rgba, core_err *err)
{
    if (!rgba)
        return core_err_set(err, -1, "render: frame: expected an image buffer");
    if (render_frame_gl(rc, sc, s, v, err) < 0)
        return -1;
    render_read_back(rc, rgba);
    if (sc->overlays & (RENDER_OVERLAY_HUD | RENDER_OVERLAY_AIRWAKE)) /* the strip, the airwake's legend */
        return render_overlay_hud(sc, s, v, rc->w, rc->h, rgba, err) < 0 ? -1 : 0;
    return 0;
}

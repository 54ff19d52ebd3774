/* test_core.c -- core: frames, quaternions, Euler angles, WOD convention,
 * units, INI getters, ship geometry. Expected values are worked by hand. */
#include "check.h"
#include "core.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define TOL 1e-12

static void vec_near(core_vec3 a, double x, double y, double z, double tol)
{
    CHECK_NEAR(a.x, x, tol);
    CHECK_NEAR(a.y, y, tol);
    CHECK_NEAR(a.z, z, tol);
}

static void test_wod(void)
{
    /* the label of titles: whole knots and degrees, ahead within 0.5 deg */
    char lab[48];
    core_wod_label(25.0 * CORE_KT_TO_MPS, 0.4, lab, sizeof lab);
    CHECK(!strcmp(lab, "25 kt ahead"));
    core_wod_label(20.0 * CORE_KT_TO_MPS, -30.0, lab, sizeof lab);
    CHECK(!strcmp(lab, "20 kt red 30"));
    core_wod_label(15.0 * CORE_KT_TO_MPS, 90.0, lab, sizeof lab);
    CHECK(!strcmp(lab, "15 kt green 90"));
    /* Green 30 at 10 m/s: from 30 deg starboard of the bow; air moves aft and
     * to port: -10 (cos 30, sin 30, 0) = (-8.660254, -5, 0). */
    vec_near(core_wod_vel_S_mps(10.0, 30.0 * CORE_DEG_TO_RAD), -8.660254037844386, -5.0, 0.0, 1e-12);
    /* Headwind: air from bow to stern (-x). */
    vec_near(core_wod_vel_S_mps(5.0, 0.0), -5.0, 0.0, 0.0, TOL);
    /* Red 90: from port, air moves to starboard (+y). */
    vec_near(core_wod_vel_S_mps(4.0, -90.0 * CORE_DEG_TO_RAD), 0.0, 4.0, 0.0, 1e-12);
    CHECK_NEAR(core_wod_wrap_deg(270.0), -90.0, TOL);
    CHECK_NEAR(core_wod_wrap_deg(-180.0), 180.0, TOL);
    /* mirror: red 30 <-> green 30, beam winds swap, head and stern stay (+0) */
    CHECK_NEAR(core_wod_mirror_deg(-30.0), 30.0, TOL);
    CHECK_NEAR(core_wod_mirror_deg(90.0), -90.0, TOL);
    CHECK_NEAR(core_wod_mirror_deg(180.0), 180.0, TOL);
    CHECK(core_wod_mirror_deg(0.0) == 0.0 && !signbit(core_wod_mirror_deg(0.0)));
    CHECK(!signbit(core_wod_mirror_deg(-0.0)));
    CHECK_NEAR(core_wod_wrap_deg(180.0), 180.0, TOL);
    CHECK_NEAR(core_wod_wrap_deg(-190.0), 170.0, TOL);
    char b[32];
    core_wod_name(30.0, b, sizeof b);
    CHECK(strcmp(b, "green 30") == 0);
    core_wod_name(-90.0, b, sizeof b);
    CHECK(strcmp(b, "red 90") == 0);
    core_wod_name(0.0, b, sizeof b);
    CHECK(strcmp(b, "head") == 0);
    /* Grid faces: a head wind blows toward -x (in by the bow face), red 90
     * toward +y; 2 deg off the beam the fore-aft component is 3.5 % of the
     * speed, under the 5 % of a symmetry plane; calm air is flagged. */
    int fs[2];
    CHECK(core_wod_faces(10.0, 0.0, fs) == 0 && fs[0] == -1 && fs[1] == 0);
    CHECK(core_wod_faces(10.0, -90.0 * CORE_DEG_TO_RAD, fs) == 0 && fs[0] == 0 && fs[1] == 1);
    CHECK(core_wod_faces(10.0, 88.0 * CORE_DEG_TO_RAD, fs) == 0 && fs[0] == 0 && fs[1] == -1);
    CHECK(core_wod_faces(10.0, 150.0 * CORE_DEG_TO_RAD, fs) == 0 && fs[0] == 1 && fs[1] == -1);
    CHECK(core_wod_faces(0.0, 0.3, fs) == 1 && fs[0] == 0 && fs[1] == 0);
    /* Units: 1 kt = 0.514444 m/s, 54 km/h = 15 m/s. */
    CHECK_NEAR(20.0 * CORE_KT_TO_MPS, 10.28888, 1e-9);
    CHECK_NEAR(54.0 * CORE_KMH_TO_MPS, 15.0, 1e-12);
}

static void test_rotations(void)
{
    /* Yaw 90 deg: body x (nose) points east in NED. */
    core_euler e = {0.0, 0.0, 90.0 * CORE_DEG_TO_RAD};
    core_quat q = core_quat_from_euler(e);
    vec_near(core_quat_rotate(q, core_vec3_make(1, 0, 0)), 0, 1, 0, 1e-12);
    /* Pitch 30 deg nose up: body x points forward and up (-z in NED). */
    core_euler p = {0.0, 30.0 * CORE_DEG_TO_RAD, 0.0};
    vec_near(core_quat_rotate(core_quat_from_euler(p), core_vec3_make(1, 0, 0)), cos(M_PI / 6), 0,
             -0.5, 1e-12);
    /* Roll 90 deg right wing down: body y (right wing) points down (+z). */
    core_euler r = {90.0 * CORE_DEG_TO_RAD, 0.0, 0.0};
    vec_near(core_quat_rotate(core_quat_from_euler(r), core_vec3_make(0, 1, 0)), 0, 0, 1, 1e-12);
    /* Gravity in body axes for pitch theta, roll phi: g (-sin t, sin f cos t, cos f cos t). */
    core_euler pr = {0.2, 0.1, 1.3};
    core_vec3 gB = core_quat_rotate_inv(core_quat_from_euler(pr), core_vec3_make(0, 0, 1));
    vec_near(gB, -sin(0.1), sin(0.2) * cos(0.1), cos(0.2) * cos(0.1), 1e-12);
    /* DCM and quaternion agree; Euler round trip. */
    core_euler a = {-0.7, 0.4, 2.5};
    core_quat qa = core_quat_from_euler(a);
    core_mat3 m = core_mat3_from_euler(a);
    core_vec3 v = core_vec3_make(0.3, -1.2, 2.0);
    core_vec3 v1 = core_quat_rotate(qa, v), v2 = core_mat3_mul_vec(m, v);
    vec_near(v1, v2.x, v2.y, v2.z, 1e-12);
    core_vec3 w1 = core_quat_rotate_inv(qa, v), w2 = core_mat3_tmul_vec(m, v);
    vec_near(w1, w2.x, w2.y, w2.z, 1e-12);
    core_euler b = core_quat_to_euler(qa);
    CHECK_NEAR(b.phi_rad, a.phi_rad, 1e-12);
    CHECK_NEAR(b.theta_rad, a.theta_rad, 1e-12);
    CHECK_NEAR(b.psi_rad, a.psi_rad, 1e-12);
    core_euler c = core_mat3_to_euler(m); /* the matrix's inverse too */
    CHECK_NEAR(c.phi_rad, a.phi_rad, 1e-12);
    CHECK_NEAR(c.theta_rad, a.theta_rad, 1e-12);
    CHECK_NEAR(c.psi_rad, a.psi_rad, 1e-12);
    /* Composition: yaw then pitch equals the 3-2-1 product. */
    core_quat qy = core_quat_from_euler((core_euler){0, 0, 2.5});
    core_quat qp = core_quat_from_euler((core_euler){0, 0.4, 0});
    core_quat qr = core_quat_from_euler((core_euler){-0.7, 0, 0});
    core_quat qc = core_quat_mul(core_quat_mul(qy, qp), qr);
    vec_near(core_quat_rotate(qc, v), v1.x, v1.y, v1.z, 1e-12);
    /* Kinematics: integrating qdot for a constant yaw rate 0.5 rad/s for 2 s gives yaw 1 rad. */
    core_quat qi = core_quat_identity();
    double dt = 1e-4;
    for (int i = 0; i < 20000; i++) {
        core_quat k1 = core_quat_deriv(qi, core_vec3_make(0, 0, 0.5));
        core_quat mid = {qi.w + 0.5 * dt * k1.w, qi.x + 0.5 * dt * k1.x, qi.y + 0.5 * dt * k1.y,
                         qi.z + 0.5 * dt * k1.z};
        core_quat k2 = core_quat_deriv(mid, core_vec3_make(0, 0, 0.5));
        qi.w += dt * k2.w;
        qi.x += dt * k2.x;
        qi.y += dt * k2.y;
        qi.z += dt * k2.z;
    }
    CHECK_NEAR(core_quat_to_euler(qi).psi_rad, 1.0, 1e-7);
}

static void test_frames(void)
{
    /* Ship heading east (yaw 90 deg) at (100, 50, 0) in E. A point 10 m
     * forward, 2 m to starboard and 3 m up in S lies at (98, 60, -3) in E. */
    core_pose ship = {core_vec3_make(100, 50, 0), core_quat_from_euler((core_euler){0, 0, M_PI / 2})};
    core_vec3 pE = core_pose_point_to_E(&ship, core_vec3_make(10, 2, -3));
    vec_near(pE, 98, 60, -3, 1e-12);
    vec_near(core_pose_point_from_E(&ship, pE), 10, 2, -3, 1e-12);
    /* A headwind over the deck of a ship heading east blows toward the west in E. */
    core_vec3 wE = core_pose_vec_to_E(&ship, core_wod_vel_S_mps(10.0, 0.0));
    vec_near(wE, 0, -10, 0, 1e-12);
    vec_near(core_pose_vec_from_E(&ship, wE), -10, 0, 0, 1e-12);
    /* Helicopter body B relative to S: chain B -> E -> S for a ship rolled 5 deg. */
    core_pose ship2 = {core_vec3_make(0, 0, 0), core_quat_from_euler((core_euler){5 * CORE_DEG_TO_RAD, 0, 0})};
    core_vec3 zS = core_pose_vec_from_E(&ship2, core_vec3_make(0, 0, 1));
    vec_near(zS, 0, sin(5 * CORE_DEG_TO_RAD), cos(5 * CORE_DEG_TO_RAD), 1e-12);
}

/* 1 if choices ("a|b|c") lists name(0) .. name(n - 1) in that order. */
static int choices_agree(const char *choices, const char *(*name)(int), int n)
{
    char buf[256] = "";
    size_t len = 0;
    for (int v = 0; v < n; v++)
        len += (size_t)snprintf(buf + len, sizeof buf - len, "%s%s", v ? "|" : "", name(v));
    return len < sizeof buf && strcmp(buf, choices) == 0;
}

static void test_range(void)
{
    double v[16];
    int n = 0;
    CHECK(core_parse_range("-90:90:30", v, 16, &n) == 0);
    CHECK(n == 7);
    CHECK_NEAR(v[0], -90, TOL);
    CHECK_NEAR(v[6], 90, TOL);
    CHECK(core_parse_range("0:150:10", v, 16, &n) == 0 && n == 16);
    CHECK(core_parse_range("12.5", v, 16, &n) == 0 && n == 1 && v[0] == 12.5);
    CHECK(core_parse_range("0:10:0", v, 16, &n) < 0);
    CHECK(core_parse_range("10:0:1", v, 16, &n) < 0);
    CHECK(core_parse_range("a:b:c", v, 16, &n) < 0);
    CHECK(core_parse_range("0:1000:1", v, 16, &n) < 0);
    /* a count past INT_MAX (or infinite) is refused, not converted to a
     * negative count and returned as success */
    n = 5;
    CHECK(core_parse_range("0:1e10:1", v, 16, &n) < 0 && n == 5);
    CHECK(core_parse_range("-90:90:1e-300", v, 16, &n) < 0 && n == 5);
    CHECK(core_parse_range("-1e308:1e308:1", v, 16, &n) < 0 && n == 5);
    /* an empty part is malformed, not skipped */
    CHECK(core_parse_range("0:10:1:", v, 16, &n) < 0);
    CHECK(core_parse_range("0::10:1", v, 16, &n) < 0);

    /* X,Y,Z: exact, or followed by what the caller allows */
    const char *end = NULL;
    CHECK(core_parse_vec3("1.5,-2,3e1", v, NULL) == 0 && v[0] == 1.5 && v[1] == -2 && v[2] == 30);
    CHECK(core_parse_vec3("1,2", v, NULL) < 0);
    CHECK(core_parse_vec3("1,2,3 ", v, NULL) < 0);
    CHECK(core_parse_vec3("1,2,x", v, NULL) < 0);
    CHECK(core_parse_vec3("1;2;3", v, NULL) < 0);
    CHECK(core_parse_vec3("1,inf,3", v, NULL) < 0);
    CHECK(core_parse_vec3("1,2,3:4,5,6", v, &end) == 0 && v[2] == 3 && end && *end == ':');

    /* grid levels: one spelling, both ways, and nothing else accepted */
    for (int l = 0; l < CORE_GRID_NLEVELS; l++)
        CHECK(core_grid_parse(core_grid_name(l)) == l);
    CHECK(strcmp(core_grid_name(1), "default") == 0);
    CHECK(strcmp(core_grid_name(4), "?") == 0 && strcmp(core_grid_name(-1), "?") == 0);
    /* the quick level: named, parsed by core_grid_parse_any only, coarsest by rank */
    CHECK(strcmp(core_grid_name(CORE_GRID_QUICK), "quick") == 0 && core_grid_parse("quick") == -1);
    CHECK(core_grid_parse_any("quick") == CORE_GRID_QUICK && core_grid_parse_any("fine") == CORE_GRID_FINE);
    CHECK(core_grid_rank(CORE_GRID_QUICK) == 0 && core_grid_rank(CORE_GRID_COARSE) == 1 &&
          core_grid_rank(CORE_GRID_DEFAULT) == 2 && core_grid_rank(CORE_GRID_FINE) == 3 && core_grid_rank(4) == -1);
    CHECK(core_grid_parse("Fine") == -1 && core_grid_parse("") == -1 && core_grid_parse(NULL) == -1);
    CHECK(core_grid_parse("default") == CORE_GRID_DEFAULT && core_grid_parse("fine") == CORE_GRID_FINE);
    CHECK(core_rotor_parse("loaded") == CORE_ROTOR_LOADED && core_rotor_parse("off") == CORE_ROTOR_OFF);
    CHECK(core_rotor_parse("Loaded") == -1 && strcmp(core_rotor_name(3), "?") == 0);
    CHECK(core_coupling_parse("one-way") == CORE_COUPLING_ONE_WAY && core_coupling_parse("oneway") == -1);
    CHECK(strcmp(core_coupling_name(CORE_COUPLING_TWO_WAY), "two-way") == 0);
    /* the INI reader's choice strings are the names in value order */
    CHECK(choices_agree(core_grid_choices(), core_grid_name, CORE_GRID_NLEVELS));
    CHECK(choices_agree(core_rotor_choices(), core_rotor_name, CORE_ROTOR_NMODES));
    CHECK(choices_agree(core_coupling_choices(), core_coupling_name, CORE_COUPLING_NMODES));
}

static const char *write_tmp(const char *name, const char *text)
{
    static char path[256];
    snprintf(path, sizeof path, "%s/%s", getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp", name);
    FILE *f = fopen(path, "w");
    fputs(text, f);
    fclose(f);
    return path;
}

static void test_ini(void)
{
    core_err err = {0};
    const char *p = write_tmp("disim_core_ini.ini",
                              "; comment\n[a]\nx = 1.5\nn = 7\nb = yes\ne = beta\n"
                              "list = 1, 2, 3\ns = hello world ; inline comment\n\n[b]\ny = oops\n");
    core_ini *ini = core_ini_load(p, &err);
    CHECK(ini != NULL);
    if (!ini)
        return;
    double x = 0;
    long n = 0;
    int b = 0, e = -1, cnt = 0;
    double l[4];
    char s[32];
    CHECK(core_ini_get_double(ini, "a", "x", 1, 0, 2, &x, &err) == 0 && x == 1.5);
    CHECK(core_ini_get_int(ini, "a", "n", 1, 0, 10, &n, &err) == 0 && n == 7);
    CHECK(core_ini_get_bool(ini, "a", "b", 1, &b, &err) == 0 && b == 1);
    CHECK(core_ini_get_enum(ini, "a", "e", 1, "alpha|beta|gamma", &e, &err) == 0 && e == 1);
    CHECK(core_ini_get_doubles(ini, "a", "list", 1, 0, 5, l, 4, &cnt, &err) == 0 && cnt == 3 &&
          l[2] == 3.0);
    CHECK(core_ini_get_string(ini, "a", "s", 1, s, sizeof s, &err) == 0 && !strcmp(s, "hello world"));
    /* Optional absent key: 1, value untouched. */
    x = 42;
    CHECK(core_ini_get_double(ini, "a", "absent", 0, 0, 1, &x, &err) == 1 && x == 42);
    /* Required absent key. */
    CHECK(core_ini_get_double(ini, "a", "absent", 1, 0, 1, &x, &err) < 0);
    CHECK(strstr(err.msg, "[a] absent: missing required key") != NULL);
    /* Wrong type names the line. */
    CHECK(core_ini_get_double(ini, "b", "y", 1, 0, 1, &x, &err) < 0);
    CHECK(strstr(err.msg, ":11: [b] y = 'oops': expected a number") != NULL);
    /* Out of range. */
    CHECK(core_ini_get_double(ini, "a", "x", 1, 0, 1, &x, &err) < 0);
    CHECK(strstr(err.msg, ":3: [a] x = 1.5: out of range, expected 0 to 1") != NULL);
    core_ini_destroy(ini);

    /* Unknown key after consuming the rest. */
    p = write_tmp("disim_core_ini2.ini", "[a]\nx = 1\nxx = 2\n[c]\nz = 1\n");
    ini = core_ini_load(p, &err);
    CHECK(core_ini_get_double(ini, "a", "x", 1, 0, 2, &x, &err) == 0);
    CHECK(core_ini_check_unused(ini, &err) < 0);
    CHECK(strstr(err.msg, ":3: [a] xx: unknown key") != NULL);
    CHECK(core_ini_get_double(ini, "a", "xx", 1, 0, 2, &x, &err) == 0);
    CHECK(core_ini_check_unused(ini, &err) < 0);
    CHECK(strstr(err.msg, ":5: [c]: unknown section") != NULL);
    core_ini_skip_section(ini, "c");
    CHECK(core_ini_check_unused(ini, &err) == 0);
    core_ini_destroy(ini);

    /* An empty item in a list is an error naming it, not skipped: "1,,2"
     * read as two numbers would shift a table's values against its
     * abscissae. */
    p = write_tmp("disim_core_ini4.ini", "[a]\nl1 = 1,,2\nl2 = 1, 2,\nl3 = ,1\nl4 =\n");
    ini = core_ini_load(p, &err);
    CHECK(ini != NULL);
    if (ini) {
        CHECK(core_ini_get_doubles(ini, "a", "l1", 1, 0, 5, l, 4, &cnt, &err) < 0);
        CHECK(strstr(err.msg, ":2: [a] l1: item 2 '': expected a number") != NULL);
        CHECK(core_ini_get_doubles(ini, "a", "l2", 1, 0, 5, l, 4, &cnt, &err) < 0);
        CHECK(strstr(err.msg, ":3: [a] l2: item 3 '': expected a number") != NULL);
        CHECK(core_ini_get_doubles(ini, "a", "l3", 1, 0, 5, l, 4, &cnt, &err) < 0);
        CHECK(strstr(err.msg, ":4: [a] l3: item 1 '': expected a number") != NULL);
        CHECK(core_ini_get_doubles(ini, "a", "l4", 1, 0, 5, l, 4, &cnt, &err) < 0);
        CHECK(strstr(err.msg, ":5: [a] l4: expected a comma-separated list of numbers") != NULL);
        core_ini_destroy(ini);
    }

    /* Syntax error and missing file. */
    p = write_tmp("disim_core_ini3.ini", "[a]\nx = 1\nthis line has no equals sign\n");
    CHECK(core_ini_load(p, &err) == NULL);
    CHECK(strstr(err.msg, ":3: syntax error") != NULL);
    CHECK(core_ini_load("/nonexistent/disim.ini", &err) == NULL);
    CHECK(strstr(err.msg, "cannot open") != NULL);
    /* A key given twice, and an indented line (inih: a continuation of the
     * key above, which replaced its value): refused naming both lines. The
     * same key in another section is fine. */
    p = write_tmp("disim_core_ini5.ini", "[a]\nx = 1\n[b]\nx = 2\ny = 3\nx = 4\n");
    CHECK(core_ini_load(p, &err) == NULL);
    CHECK(strstr(err.msg, ":6: [b] x: given again (first at line 4)") != NULL);
    p = write_tmp("disim_core_ini6.ini", "[wod]\ndir_deg = -90:90:30\n   0:30:30\n");
    CHECK(core_ini_load(p, &err) == NULL);
    CHECK(strstr(err.msg, ":3: [wod] dir_deg: given again (first at line 2)") != NULL);
    /* the first repeat is named, and a syntax error before it comes first */
    p = write_tmp("disim_core_ini7.ini", "[a]\nx = 1\nx = 2\nx = 3\n");
    CHECK(core_ini_load(p, &err) == NULL && strstr(err.msg, ":3: [a] x: given again (first at line 2)") != NULL);
    p = write_tmp("disim_core_ini8.ini", "[a]\nx = 1\nno equals here\nx = 2\n");
    CHECK(core_ini_load(p, &err) == NULL && strstr(err.msg, ":3: syntax error") != NULL);
    /* A folder opens, but reading it fails: an error, not an empty file
     * whose keys are then all "missing". */
    ini = core_ini_load("scenarios", &err);
    CHECK(ini == NULL);
    core_ini_destroy(ini);
    CHECK(strstr(err.msg, "scenarios: a folder, expected a regular file") != NULL);
    core_ini_destroy(NULL);
}

static const char *write_bytes(const char *name, const char *bytes, size_t n)
{
    static char path[256];
    snprintf(path, sizeof path, "%s/%s", getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp", name);
    FILE *f = fopen(path, "wb");
    fwrite(bytes, 1, n, f);
    fclose(f);
    return path;
}

/* Loads text that must be refused; 1 if err names what was expected. */
static int refused(const char *bytes, size_t n, const char *expect)
{
    core_err err = {0};
    core_ini *ini = core_ini_load(write_bytes("disim_core_text.ini", bytes, n), &err);
    core_ini_destroy(ini);
    if (!ini && strstr(err.msg, expect))
        return 1;
    fprintf(stderr, "expected '%s', got '%s'\n", expect, ini ? "(loaded)" : err.msg);
    return 0;
}

/* What the reader takes as text, numbers and names, and what it refuses:
 * file, line and column named. */
static void test_ini_text(void)
{
#define T(s) s, sizeof s - 1
    CHECK(refused(T("[a]\nx = 1\ny = ab\0cd\n"), ":3:7: a NUL byte"));
    CHECK(refused(T("[a]\nx = a\033[31m\n"), ":2:6: byte 0x1B, a control character"));
    CHECK(refused(T("[a]\nx = a\177\n"), ":2:6: byte 0x7F, a control character"));
    CHECK(refused(T("[a]\nx = caf\351\n"), ":2:8: byte 0xE9, a byte that is not UTF-8"));
    CHECK(refused(T("[a]\nx = \300\257\n"), ":2:5: byte 0xC0, a byte that is not UTF-8")); /* overlong '/' */
    CHECK(refused(T("[a]\nx = \355\240\200\n"), ":2:5: byte 0xED")); /* a surrogate */
    CHECK(refused(T("[a]\nx = \364\220\200\200\n"), ":2:5: byte 0xF4")); /* past U+10FFFF */
    CHECK(refused(T("[a]\nx = caf\303\n"), ":2:8: byte 0xC3")); /* cut sequence */
    /* tabs, CRLF, a BOM and UTF-8 are text */
    core_err err = {0};
    const char ok[] = "\357\273\277[a]\r\nx\t= 20\r\ns = caf\303\251 \342\202\254 \360\237\232\201\n"
                      "h = 0x14\nn = 1e3\nm = -.5\nk = +2.\nname = UH-60A\nbad1 = ../../escaped\nbad2 = .hidden\n"
                      "bad3 = a b\nl = 1, 0x2\n";
    core_ini *ini = core_ini_load(write_bytes("disim_core_text_ok.ini", T(ok)), &err);
    CHECK(ini != NULL);
    if (ini) {
        double x;
        char s[64];
        double l[2];
        int cnt;
        CHECK(core_ini_get_double(ini, "a", "x", 1, 0, 100, &x, &err) == 0 && x == 20.0);
        CHECK(core_ini_get_string(ini, "a", "s", 1, s, sizeof s, &err) == 0 && !strcmp(s, "caf\303\251 \342\202\254 \360\237\232\201"));
        /* decimal only: strtod would read 0x14 as 20 */
        CHECK(core_ini_get_double(ini, "a", "h", 1, 0, 100, &x, &err) < 0 &&
              strstr(err.msg, ":4: [a] h = '0x14': expected a number"));
        CHECK(core_ini_get_double(ini, "a", "n", 1, 0, 1e4, &x, &err) == 0 && x == 1000.0);
        CHECK(core_ini_get_double(ini, "a", "m", 1, -1, 1, &x, &err) == 0 && x == -0.5);
        CHECK(core_ini_get_double(ini, "a", "k", 1, -1, 3, &x, &err) == 0 && x == 2.0);
        CHECK(core_ini_get_doubles(ini, "a", "l", 1, 0, 5, l, 2, &cnt, &err) < 0 &&
              strstr(err.msg, "item 2 '0x2': expected a number"));
        CHECK(core_ini_get_name(ini, "a", "name", 1, s, sizeof s, &err) == 0 && !strcmp(s, "UH-60A"));
        CHECK(core_ini_get_name(ini, "a", "bad1", 1, s, sizeof s, &err) < 0 &&
              strstr(err.msg, ":9: [a] bad1 = '../../escaped': expected a name"));
        CHECK(core_ini_get_name(ini, "a", "bad2", 1, s, sizeof s, &err) < 0);
        CHECK(core_ini_get_name(ini, "a", "bad3", 1, s, sizeof s, &err) < 0);
        core_ini_destroy(ini);
    }
    /* the same reader on text in memory: the name in every message, its
     * folder for relative paths, a NUL inside the length refused, text
     * after the length not read */
    const char mem[] = "[a]\nx = 1\np = b/c.ini\ny = z\0w\n";
    ini = core_ini_parse(mem, 15, "dir/mem.ini", &err);
    CHECK(ini != NULL && core_ini_count(ini) == 2 && !strcmp(core_ini_path(ini), "dir/mem.ini"));
    if (ini) {
        char s[64];
        CHECK(core_ini_get_path(ini, "a", "p", 1, s, sizeof s, &err) < 0 &&
              strstr(err.msg, "dir/mem.ini:3: [a] p = 'b': file not found (looked for dir/b)"));
        core_ini_destroy(ini);
    }
    CHECK(core_ini_parse(mem, sizeof mem - 1, "dir/mem.ini", &err) == NULL &&
          strstr(err.msg, "dir/mem.ini:4:6: a NUL byte"));
    ini = core_ini_parse("", 0, "empty.ini", &err);
    CHECK(ini != NULL && core_ini_count(ini) == 0);
    core_ini_destroy(ini);
#undef T
    double rv[1];
    int rn;
    CHECK(core_parse_range("0x10", rv, 1, &rn) < 0);
    /* not regular files, and the size cap */
    CHECK(core_ini_load("/dev/zero", &err) == NULL && strstr(err.msg, "/dev/zero: a character device, expected a regular file"));
    CHECK(core_file_regular("/dev/null", 10, &err) < 0 && strstr(err.msg, "a character device"));
    const char *big = write_bytes("disim_core_big.ini", "", 0);
    CHECK(truncate(big, CORE_INI_MAX_BYTES + 1) == 0);
    CHECK(core_ini_load(big, &err) == NULL && strstr(err.msg, "larger than the 16777216 bytes"));
    CHECK(core_file_regular(big, -1, &err) == 0);
    CHECK(core_file_regular(big, CORE_INI_MAX_BYTES + 1, &err) == 0);
    remove(big);
    CHECK(core_file_regular("/nonexistent/x", -1, &err) < 0 && strstr(err.msg, "cannot open"));
    char fifo[256];
    snprintf(fifo, sizeof fifo, "%s/disim_core_fifo.%ld", getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp", (long)getpid());
    CHECK(mkfifo(fifo, 0600) == 0);
    CHECK(core_ini_load(fifo, &err) == NULL && strstr(err.msg, "a FIFO, expected a regular file"));
    remove(fifo);
}

static void test_ship(void)
{
    core_ship ship;
    core_err err = {0};
    CHECK(core_ship_load("scenarios/ships/sfs2.ini", &ship, &err) == 0);
    if (err.msg[0])
        fprintf(stderr, "%s\n", err.msg);
    CHECK(ship.nblocks == 3);
    CHECK_NEAR(ship.length_m, 138.7, 1e-9);
    /* The landing spot is on the deck: the point just below it is inside the
     * hull, just above it is free air. */
    CHECK(core_ship_contains(&ship, core_vec3_make(0, 0, 0.1)));
    CHECK(!core_ship_contains(&ship, core_vec3_make(0, 0, -0.1)));
    /* Hangar face at x = 12 m, 7.6 m tall above the deck. */
    CHECK(core_ship_contains(&ship, core_vec3_make(12.5, 0, -7.0)));
    CHECK(!core_ship_contains(&ship, core_vec3_make(11.5, 0, -7.0)));
    CHECK(!core_ship_contains(&ship, core_vec3_make(12.5, 0, -7.8)));
    /* Bow taper: at the bow tip the hull is a point on the centre line. */
    CHECK(core_ship_contains(&ship, core_vec3_make(126.0, 0, 1.0)));
    CHECK(!core_ship_contains(&ship, core_vec3_make(126.0, 3.0, 1.0)));
    CHECK(core_ship_contains(&ship, core_vec3_make(90.0, 6.0, 1.0)));
    core_ship s2;
    /* Port-starboard symmetry: SFS2, CG-47 and LPD-17 (its superstructure on
     * the centre line) are symmetric as modelled; a CG-47 with its hangar
     * moved 0.1 m to starboard is not, nor a ship with a block's mirror
     * twin missing. */
    CHECK(core_ship_mirror_symmetric(&ship, 1e-6) == 1);
    CHECK(core_ship_load("scenarios/ships/cg47.ini", &s2, &err) == 0);
    CHECK(core_ship_mirror_symmetric(&s2, 1e-6) == 1);
    for (int i = 0; i < s2.nblocks; i++)
        if (!strcmp(s2.blocks[i].name, "hangar")) {
            s2.blocks[i].y0_m += 0.1;
            s2.blocks[i].y1_m += 0.1;
        }
    CHECK(core_ship_mirror_symmetric(&s2, 1e-6) == 0);
    CHECK(core_ship_mirror_symmetric(&s2, 0.2) == 1);
    core_ship pair;
    memset(&pair, 0, sizeof pair);
    pair.nblocks = 2;
    pair.blocks[0] = (core_ship_block){"port", 0, 10, -6, -2, -5, 0, 0};
    pair.blocks[1] = (core_ship_block){"stbd", 0, 10, 2, 6, -5, 0, 0};
    CHECK(core_ship_mirror_symmetric(&pair, 1e-6) == 1);
    pair.blocks[1] = pair.blocks[0]; /* two port blocks: no starboard twin */
    CHECK(core_ship_mirror_symmetric(&pair, 1e-6) == 0);
    CHECK(core_ship_load("scenarios/ships/lpd17.ini", &s2, &err) == 0);
    CHECK(core_ship_mirror_symmetric(&s2, 1e-6) == 1);
    /* Every ship of the folder, found by a key's ship name or its prefix
     * ("SFS2" of "SFS2.isolated"); a prefix of a name is not that name. */
    core_ship *all = NULL;
    int nall = 0;
    CHECK(core_ship_load_dir("scenarios/ships", &all, &nall, &err) == 0 && nall == 3);
    const char *iso = "SFS2.isolated";
    const core_ship *found = core_ship_find(all, nall, iso, 4);
    CHECK(found && !strcmp(found->name, "SFS2"));
    CHECK(core_ship_find(all, nall, "CG-47", 5) && core_ship_find(all, nall, "CG-4", 4) == NULL);
    CHECK(core_ship_find(all, nall, iso, strlen(iso)) == NULL);
    free(all);
    /* A block whose top is below its bottom names the line. */
    const char *p = write_tmp("disim_bad_ship.ini",
                              "[ship]\nname = X\nlength_m = 10\nbeam_m = 2\ndraft_m = 1\n"
                              "deck_height_m = 2\ndeck_x_m = -1, 1\ndeck_halfwidth_m = 1\n"
                              "anemometer_S_m = 0, 0, -5\n[block hull]\nx_m = -5, 5\ny_m = -1, 1\n"
                              "height_m = 3, 0\n");
    CHECK(core_ship_load(p, &s2, &err) < 0);
    CHECK(strstr(err.msg, ":13: [block hull] height_m = 3, 0: expected the first below the second") != NULL);
    /* A block name too long for core_ship_block.name is refused: cut, it
     * never matched its section again and the block came in once per key. */
    const char *head = "[ship]\nname = X\nlength_m = 10\nbeam_m = 2\ndraft_m = 1\n"
                       "deck_height_m = 2\ndeck_x_m = -1, 1\ndeck_halfwidth_m = 1\n"
                       "anemometer_S_m = 0, 0, -5\n";
    char text[1024];
    snprintf(text, sizeof text, "%s[block %s]\nx_m = -5, 5\ny_m = -1, 1\nheight_m = 0, 3\n", head,
             "superstructure_forward_of_the_hangar");
    p = write_tmp("disim_bad_ship2.ini", text);
    CHECK(core_ship_load(p, &s2, &err) < 0);
    CHECK(strstr(err.msg, ":11: [block superstructure_forward_of_the_hangar]: expected a block name of "
                          "1 to 31 characters") != NULL);
    snprintf(text, sizeof text, "%s[block %s]\nx_m = -5, 5\ny_m = -1, 1\nheight_m = 0, 3\n", head,
             "superstructure_forward_of_hanga"); /* 31 characters: fits */
    p = write_tmp("disim_ship_31.ini", text);
    CHECK(core_ship_load(p, &s2, &err) == 0 && s2.nblocks == 1);
}

static int nlog = 0;
static void sink(void *user, int level, const char *msg)
{
    (void)level;
    nlog++;
    snprintf(user, 64, "%s", msg);
}

static void test_log(void)
{
    char last[64] = "";
    core_log log = {sink, last, CORE_LOG_INFO};
    core_log_msg(&log, CORE_LOG_INFO, "value %d", 3);
    core_log_msg(&log, CORE_LOG_DEBUG, "dropped");
    core_log_msg(NULL, CORE_LOG_ERROR, "no sink");
    CHECK(nlog == 1);
    CHECK(strcmp(last, "value 3") == 0);
}

/* core_str: text appended past any first capacity arrives whole, in order;
 * an empty buffer gives ""; take leaves the buffer empty for reuse. */
static void test_str(void)
{
    core_str b = {0};
    char *e = core_str_take(&b);
    CHECK(e != NULL && e[0] == '\0');
    free(e);
    size_t want = 0;
    for (int i = 0; i < 2000; i++) {
        CHECK(core_str_printf(&b, "| row %d | %s |\n", i, i % 7 ? "x" : "a longer cell of text") == 0);
        want += (size_t)snprintf(NULL, 0, "| row %d | %s |\n", i, i % 7 ? "x" : "a longer cell of text");
    }
    CHECK(b.len == want && b.s && strlen(b.s) == want);
    CHECK(b.s && strstr(b.s, "| row 0 | a longer cell of text |\n| row 1 | x |") == b.s);
    CHECK(b.s && strstr(b.s, "| row 1999 | x |\n") == b.s + want - strlen("| row 1999 | x |\n"));
    char *t = core_str_take(&b);
    CHECK(t != NULL && b.s == NULL && b.len == 0 && b.cap == 0);
    free(t);
    /* a failed buffer appends nothing and gives NULL */
    core_str f = {0};
    CHECK(core_str_printf(&f, "kept") == 0);
    f.failed = 1;
    CHECK(core_str_printf(&f, "dropped") == -1 && strcmp(f.s, "kept") == 0);
    CHECK(core_str_take(&f) == NULL && f.s == NULL && f.failed == 0);
}

/* mkdir -p without a shell: a quote and a space in the name, parents made,
 * a file in the way refused naming it. */
/* core_escape: terminal controls, DEL and non-ASCII escaped, a backslash
 * kept (escaping twice changes nothing), the cut never inside an escape */
static void test_escape(void)
{
    char out[64];
    CHECK(core_escape("a\x1b[2J\\b\x7f\xc3\xa9", out, sizeof out) == strlen(out));
    CHECK(!strcmp(out, "a\\x1b[2J\\b\\x7f\\xc3\\xa9"));
    char twice[64];
    CHECK(core_escape(out, twice, sizeof twice) == strlen(out) && !strcmp(twice, out));
    CHECK(core_escape("ab\x01", out, 5) == 2 && !strcmp(out, "ab"));
    CHECK(core_escape(NULL, out, sizeof out) == 0 && out[0] == '\0');
    CHECK(core_escape("plain text, 1.0 %", out, sizeof out) == 17 && !strcmp(out, "plain text, 1.0 %"));
}

/* core_crc64: CRC-64/XZ's check value (the CRC catalogue of R. Williams
 * and G. Cook, "CRC-64/XZ": check 0x995dc9bbdf1939fa for "123456789"),
 * the empty string's 0, and the eight-byte steps against the bit-wise
 * definition over every length and alignment up to 40 bytes, in one call
 * and carried on in two. */
static uint64_t crc64_bitwise(const unsigned char *p, size_t n)
{
    uint64_t c = ~0ULL;
    for (size_t i = 0; i < n; i++) {
        c ^= p[i];
        for (int b = 0; b < 8; b++)
            c = c & 1 ? (c >> 1) ^ 0xC96C5795D7870F42ULL : c >> 1;
    }
    return ~c;
}

static void test_crc64(void)
{
    CHECK(core_crc64(0, "123456789", 9) == 0x995DC9BBDF1939FAULL);
    CHECK(core_crc64(0, "", 0) == 0);
    unsigned char buf[48];
    for (size_t i = 0; i < sizeof buf; i++)
        buf[i] = (unsigned char)(i * 37u + 11u);
    int bad = 0;
    for (size_t off = 0; off < 8; off++)
        for (size_t n = 0; off + n <= 40; n++) {
            uint64_t want = crc64_bitwise(buf + off, n);
            bad += core_crc64(0, buf + off, n) != want;
            for (size_t k = 0; k <= n; k++)
                bad += core_crc64(core_crc64(0, buf + off, k), buf + off + k, n - k) != want;
        }
    CHECK(bad == 0);
}

static void log_keep(void *user, int level, const char *line)
{
    (void)level;
    snprintf(user, 64, "%s", line);
}

/* An error or a log line naming a path from the command line: the bytes a
 * terminal acts on come out as \xNN, the rest as it was */
static void test_err_printable(void)
{
    core_err e = {0};
    CHECK(core_err_set(&e, -3, "%s: missing", "run\x1b]0;owned\x07\n\xc3\xa9.ini") == -3 && e.code == -3);
    CHECK(!strcmp(e.msg, "run\\x1b]0;owned\\x07\\x0a\\xc3\\xa9.ini: missing"));
    core_err_set(&e, -1, "%s", "a\\b 100 %");
    CHECK(!strcmp(e.msg, "a\\b 100 %"));
    char line[64] = "";
    core_log lg = {.fn = log_keep, .user = line, .max_level = CORE_LOG_INFO};
    core_log_msg(&lg, CORE_LOG_INFO, "loaded %s", "x\x1b[2J");
    CHECK(!strcmp(line, "loaded x\\x1b[2J"));
}

static void test_mkdir(void)
{
    char base[256], dir[512], file[512];
    snprintf(base, sizeof base, "%s/disim_core_mkdir_%d", getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp", (int)getpid());
    snprintf(dir, sizeof dir, "%s/it's a/b", base);
    core_err err = {0};
    CHECK(core_mkdir_p(dir, &err) == 0);
    struct stat st;
    CHECK(stat(dir, &st) == 0 && S_ISDIR(st.st_mode));
    CHECK(core_mkdir_p(dir, &err) == 0); /* there already */
    snprintf(file, sizeof file, "%s/f", base);
    FILE *f = fopen(file, "w");
    CHECK(f != NULL);
    if (f)
        fclose(f);
    char under[600];
    snprintf(under, sizeof under, "%s/g", file);
    CHECK(core_mkdir_p(under, &err) < 0 && strstr(err.msg, file) != NULL);
    CHECK(core_mkdir_p(file, &err) < 0 && strstr(err.msg, "not a folder") != NULL);
    CHECK(core_mkdir_p("", &err) < 0);
    /* checked before any work, nothing created */
    char deep[700];
    snprintf(deep, sizeof deep, "%s/new/deeper", dir);
    CHECK(core_dir_check(deep, &err) == 0 && stat(deep, &st) != 0);
    CHECK(core_dir_check(dir, &err) == 0);
    CHECK(core_dir_check(file, &err) < 0 && strstr(err.msg, ": not a folder") != NULL);
    CHECK(core_dir_check(under, &err) < 0 && strstr(err.msg, "not a folder (on the way to the folder") != NULL);
    CHECK(core_dir_check("/dev/null/x", &err) < 0 && strstr(err.msg, "/dev/null: not a folder") != NULL);
    CHECK(core_dir_check("", &err) < 0);
    /* outputs: a regular file or a new name; the same file spelt twice */
    CHECK(core_output_check(file, &err) == 0 && core_output_check(deep, &err) == 0);
    CHECK(core_output_check(dir, &err) < 0 && strstr(err.msg, "a folder: expected a regular file"));
    CHECK(core_output_check("/dev/full", &err) < 0 && strstr(err.msg, "a character device"));
    char again[700];
    snprintf(again, sizeof again, "%s/it's a/../f", base);
    CHECK(core_path_same(file, again) == 1);
    snprintf(again, sizeof again, "%s/it's a/../new.csv", base);
    snprintf(deep, sizeof deep, "%s/./new.csv", base);
    CHECK(core_path_same(deep, again) == 1);
    CHECK(core_path_same(file, deep) == 0 && core_path_same(file, NULL) == 0);
    remove(file);
    rmdir(dir);
    snprintf(dir, sizeof dir, "%s/it's a", base);
    rmdir(dir);
    rmdir(base);
}

int main(void)
{
    test_wod();
    test_rotations();
    test_frames();
    test_range();
    test_ini();
    test_ini_text();
    test_ship();
    test_log();
    test_str();
    test_escape();
    test_crc64();
    test_err_printable();
    test_mkdir();
    return check_done("test_core");
}

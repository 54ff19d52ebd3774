/* vec.c -- vectors, quaternions, direction cosines and frame poses.
 *
 * Model: rigid-body rotations as unit quaternions q_AB with v_A = q v_B q*;
 * Euler angles are the aerospace 3-2-1 sequence (yaw psi about z, pitch theta
 * about the new y, roll phi about the new x). Reference: Stevens, Lewis and
 * Johnson, "Aircraft Control and Simulation", 3rd ed., eqs. (1.3-20) (DCM from
 * Euler angles), (1.8-8) (quaternion from Euler angles), (1.8-15) (quaternion
 * kinematics qdot = q (0, w)/2).
 */
#include "core.h"

#include <math.h>

core_vec3 core_vec3_make(double x, double y, double z)
{
    core_vec3 v = {x, y, z};
    return v;
}
double core_wrap_pi(double a_rad) { return atan2(sin(a_rad), cos(a_rad)); }

core_vec3 core_vec3_add(core_vec3 a, core_vec3 b) { return core_vec3_make(a.x + b.x, a.y + b.y, a.z + b.z); }
core_vec3 core_vec3_sub(core_vec3 a, core_vec3 b) { return core_vec3_make(a.x - b.x, a.y - b.y, a.z - b.z); }
core_vec3 core_vec3_scale(core_vec3 a, double s) { return core_vec3_make(a.x * s, a.y * s, a.z * s); }
double core_vec3_dot(core_vec3 a, core_vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
core_vec3 core_vec3_cross(core_vec3 a, core_vec3 b)
{
    return core_vec3_make(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
double core_vec3_norm(core_vec3 a) { return sqrt(core_vec3_dot(a, a)); }

core_quat core_quat_identity(void)
{
    core_quat q = {1, 0, 0, 0};
    return q;
}

core_quat core_quat_mul(core_quat a, core_quat b)
{
    core_quat r;
    r.w = a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z;
    r.x = a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y;
    r.y = a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x;
    r.z = a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w;
    return r;
}

core_quat core_quat_conj(core_quat q)
{
    core_quat r = {q.w, -q.x, -q.y, -q.z};
    return r;
}

core_quat core_quat_normalize(core_quat q)
{
    double n = sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
    if (n <= 0.0)
        return core_quat_identity();
    core_quat r = {q.w / n, q.x / n, q.y / n, q.z / n};
    return r;
}

core_vec3 core_quat_rotate(core_quat q, core_vec3 v)
{
    /* v' = v + 2 w (u x v) + 2 u x (u x v), u = vector part: cheaper than two products. */
    core_vec3 u = {q.x, q.y, q.z};
    core_vec3 t = core_vec3_scale(core_vec3_cross(u, v), 2.0);
    return core_vec3_add(core_vec3_add(v, core_vec3_scale(t, q.w)), core_vec3_cross(u, t));
}

core_vec3 core_quat_rotate_inv(core_quat q, core_vec3 v) { return core_quat_rotate(core_quat_conj(q), v); }

core_quat core_quat_from_euler(core_euler e)
{
    double cp = cos(0.5 * e.phi_rad), sp = sin(0.5 * e.phi_rad);
    double ct = cos(0.5 * e.theta_rad), st = sin(0.5 * e.theta_rad);
    double cs = cos(0.5 * e.psi_rad), ss = sin(0.5 * e.psi_rad);
    core_quat q;
    q.w = cs * ct * cp + ss * st * sp;
    q.x = cs * ct * sp - ss * st * cp;
    q.y = cs * st * cp + ss * ct * sp;
    q.z = ss * ct * cp - cs * st * sp;
    return q;
}

core_euler core_quat_to_euler(core_quat q)
{
    q = core_quat_normalize(q);
    core_euler e;
    double s = 2.0 * (q.w * q.y - q.x * q.z);
    if (s > 1.0)
        s = 1.0;
    if (s < -1.0)
        s = -1.0;
    e.theta_rad = asin(s);
    e.phi_rad = atan2(2.0 * (q.w * q.x + q.y * q.z), 1.0 - 2.0 * (q.x * q.x + q.y * q.y));
    e.psi_rad = atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z));
    return e;
}

core_quat core_quat_deriv(core_quat q, core_vec3 w)
{
    core_quat wq = {0.0, w.x, w.y, w.z};
    core_quat d = core_quat_mul(q, wq);
    d.w *= 0.5;
    d.x *= 0.5;
    d.y *= 0.5;
    d.z *= 0.5;
    return d;
}

core_mat3 core_mat3_from_euler(core_euler e)
{
    double cf = cos(e.phi_rad), sf = sin(e.phi_rad);
    double ct = cos(e.theta_rad), st = sin(e.theta_rad);
    double cs = cos(e.psi_rad), ss = sin(e.psi_rad);
    /* C_AB = C_BA^T, where C_BA is Stevens & Lewis eq. (1.3-20). */
    core_mat3 m = {{{ct * cs, sf * st * cs - cf * ss, cf * st * cs + sf * ss},
                    {ct * ss, sf * st * ss + cf * cs, cf * st * ss - sf * cs},
                    {-st, sf * ct, cf * ct}}};
    return m;
}

core_euler core_mat3_to_euler(core_mat3 m)
{
    core_euler e;
    e.theta_rad = asin(fmax(-1.0, fmin(1.0, -m.m[2][0])));
    e.phi_rad = atan2(m.m[2][1], m.m[2][2]);
    e.psi_rad = atan2(m.m[1][0], m.m[0][0]);
    return e;
}

core_vec3 core_mat3_mul_vec(core_mat3 m, core_vec3 v)
{
    return core_vec3_make(m.m[0][0] * v.x + m.m[0][1] * v.y + m.m[0][2] * v.z,
                          m.m[1][0] * v.x + m.m[1][1] * v.y + m.m[1][2] * v.z,
                          m.m[2][0] * v.x + m.m[2][1] * v.y + m.m[2][2] * v.z);
}

core_vec3 core_mat3_tmul_vec(core_mat3 m, core_vec3 v)
{
    return core_vec3_make(m.m[0][0] * v.x + m.m[1][0] * v.y + m.m[2][0] * v.z,
                          m.m[0][1] * v.x + m.m[1][1] * v.y + m.m[2][1] * v.z,
                          m.m[0][2] * v.x + m.m[1][2] * v.y + m.m[2][2] * v.z);
}

core_vec3 core_pose_point_to_E(const core_pose *f, core_vec3 p)
{
    return core_vec3_add(f->pos_E_m, core_quat_rotate(f->q_EF, p));
}
core_vec3 core_pose_point_from_E(const core_pose *f, core_vec3 p)
{
    return core_quat_rotate_inv(f->q_EF, core_vec3_sub(p, f->pos_E_m));
}
core_vec3 core_pose_vec_to_E(const core_pose *f, core_vec3 v) { return core_quat_rotate(f->q_EF, v); }
core_vec3 core_pose_vec_from_E(const core_pose *f, core_vec3 v) { return core_quat_rotate_inv(f->q_EF, v); }

/* The simulated Panda's 1 kHz cycle in C: the common cycle of hri_teleop/sim/arm.py, many per call.
 *
 * SimArm._cycle and JointMotion.step (Python) stay the reference and handle every rare cycle:
 * this file runs a cycle only when the arm follows a finite command, passes the Cartesian judge,
 * touches no new workspace wall and its joints pass theirs; at any other cycle it stops and
 * returns how many it ran, so Python runs that cycle (events, reflexes, the timeout's ramp).
 * The Cartesian arithmetic is Python's, operation by operation (same doubles); the joints' forward
 * kinematics, Jacobian and 7x7 solve are pinocchio's and LAPACK's, to rounding.
 * Built by pip as an optional extension; loaded with ctypes (no Python API, any Python version).
 */
#include <math.h>

/* Cartesian state (read and written): the layout of arm_kernel.STATE_FIELDS. */
enum {
    S_TIME = 0, S_POS = 1, S_QUAT = 4, S_HELD = 8, S_HELD_TIME = 14, S_COMMANDED = 15, S_ACCEL = 21,
    S_VELOCITY = 27, S_RAMP_FROM = 33, S_RAMP_START = 39, S_RAMP_S = 40, S_WALL = 41, S_SIZE = 47
};
/* Constants: arm_kernel.PARAM_FIELDS. */
enum { P_DT = 0, P_TIMEOUT = 1, P_INTERPOLATE = 2, P_BOUNDS = 3, P_LO = 9, P_HI = 12, P_JOINTS = 15, P_SIZE = 16 };
/* Joint state: q, velocity, commanded joint velocity, its acceleration (7 each). */
enum { J_Q = 0, J_VELOCITY = 7, J_COMMANDED = 14, J_ACCEL = 21, J_SIZE = 28 };
/* Joint constants: limits, elbow, then per joint (type, axis, R, p) and the tool frame (R, p). */
enum { K_LOW = 0, K_HIGH = 7, K_VMAX = 14, K_AMAX = 21, K_JMAX = 28, K_ELBOW = 35, K_JOINT = 36,
       K_JOINT_SIZE = 16, K_FRAME = 36 + 7 * 16, K_SIZE = 36 + 7 * 16 + 12 };
/* Joint types, as pinocchio names them: JointModelRX, RY, RZ, RevoluteUnaligned. */
enum { REVOLUTE_X = 0, REVOLUTE_Y = 1, REVOLUTE_Z = 2, REVOLUTE_AXIS = 3 };

typedef struct { double r[9]; double p[3]; } Placement;  /* rotation row-major, translation */

static void compose(const Placement *a, const Placement *b, Placement *out) {
    /* out = a * b: R = Ra Rb, p = pa + Ra pb (pinocchio's SE3 product) */
    Placement o;
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++) {
            o.r[3 * i + j] = a->r[3 * i] * b->r[j] + a->r[3 * i + 1] * b->r[3 + j] + a->r[3 * i + 2] * b->r[6 + j];
        }
        o.p[i] = a->p[i] + (a->r[3 * i] * b->p[0] + a->r[3 * i + 1] * b->p[1] + a->r[3 * i + 2] * b->p[2]);
    }
    *out = o;
}

static void joint_rotation(int type, const double *axis, double q, Placement *out) {
    double s = sin(q), c = cos(q);
    for (int i = 0; i < 9; i++) out->r[i] = 0.0;
    out->p[0] = out->p[1] = out->p[2] = 0.0;
    if (type == REVOLUTE_X) {
        out->r[0] = 1.0; out->r[4] = c; out->r[5] = -s; out->r[7] = s; out->r[8] = c;
    } else if (type == REVOLUTE_Y) {
        out->r[0] = c; out->r[2] = s; out->r[4] = 1.0; out->r[6] = -s; out->r[8] = c;
    } else if (type == REVOLUTE_Z) {
        out->r[0] = c; out->r[1] = -s; out->r[3] = s; out->r[4] = c; out->r[8] = 1.0;
    } else {  /* Rodrigues about a unit axis */
        double x = axis[0], y = axis[1], z = axis[2], v = 1.0 - c;
        out->r[0] = c + x * x * v;     out->r[1] = x * y * v - z * s; out->r[2] = x * z * v + y * s;
        out->r[3] = y * x * v + z * s; out->r[4] = c + y * y * v;     out->r[5] = y * z * v - x * s;
        out->r[6] = z * x * v - y * s; out->r[7] = z * y * v + x * s; out->r[8] = c + z * z * v;
    }
}

static void load_placement(const double *k, Placement *out) {
    for (int i = 0; i < 9; i++) out->r[i] = k[i];
    for (int i = 0; i < 3; i++) out->p[i] = k[9 + i];
}

/* The tool frame's placement and its Jacobian (6 x 7, base-frame axes, row-major) at q. */
static void kinematics(const double *k, const double *q, Placement *tool, double jac[6][7]) {
    Placement world = {{1, 0, 0, 0, 1, 0, 0, 0, 1}, {0, 0, 0}};
    double axes[7][3], origins[7][3];
    for (int i = 0; i < 7; i++) {
        const double *joint = k + K_JOINT + K_JOINT_SIZE * i;
        int type = (int)joint[0];
        Placement placement, motion, local;
        load_placement(joint + 4, &placement);
        joint_rotation(type, joint + 1, q[i], &motion);
        compose(&placement, &motion, &local);
        compose(&world, &local, &world);
        const double *a = joint + 1;
        for (int r = 0; r < 3; r++) {
            axes[i][r] = world.r[3 * r] * a[0] + world.r[3 * r + 1] * a[1] + world.r[3 * r + 2] * a[2];
            origins[i][r] = world.p[r];
        }
    }
    Placement frame;
    load_placement(k + K_FRAME, &frame);
    compose(&world, &frame, tool);
    const double *f = tool->p;
    for (int i = 0; i < 7; i++) {
        const double *z = axes[i], *o = origins[i];
        /* pinocchio: the world-frame column (o x z, z), then shifted to the frame's origin */
        double v0 = o[1] * z[2] - o[2] * z[1], v1 = o[2] * z[0] - o[0] * z[2], v2 = o[0] * z[1] - o[1] * z[0];
        jac[0][i] = v0 - (f[1] * z[2] - f[2] * z[1]);
        jac[1][i] = v1 - (f[2] * z[0] - f[0] * z[2]);
        jac[2][i] = v2 - (f[0] * z[1] - f[1] * z[0]);
        jac[3][i] = z[0];
        jac[4][i] = z[1];
        jac[5][i] = z[2];
    }
}

/* Solve a x = b for two right-hand sides (LU, partial pivoting); 0 when a pivot is exactly zero. */
static int solve7(double a[7][7], double b[7][2]) {
    for (int col = 0; col < 7; col++) {
        int pivot = col;
        for (int r = col + 1; r < 7; r++) {
            if (fabs(a[r][col]) > fabs(a[pivot][col])) pivot = r;
        }
        if (a[pivot][col] == 0.0) return 0;
        if (pivot != col) {
            for (int c = 0; c < 7; c++) { double t = a[col][c]; a[col][c] = a[pivot][c]; a[pivot][c] = t; }
            for (int c = 0; c < 2; c++) { double t = b[col][c]; b[col][c] = b[pivot][c]; b[pivot][c] = t; }
        }
        for (int r = col + 1; r < 7; r++) {
            double m = a[r][col] / a[col][col];
            if (m == 0.0) continue;
            for (int c = col; c < 7; c++) a[r][c] -= m * a[col][c];
            b[r][0] -= m * b[col][0];
            b[r][1] -= m * b[col][1];
        }
    }
    for (int r = 6; r >= 0; r--) {
        for (int c = 0; c < 2; c++) {
            double s = b[r][c];
            for (int j = r + 1; j < 7; j++) s -= a[r][j] * b[j][c];
            b[r][c] = s / a[r][r];
        }
    }
    return 1;
}

/* The rotation vector of a rotation matrix (pinocchio's log3) for the small turns of one cycle;
   0 when the turn is too large for this cycle to be a common one. */
static int log3(const double r[9], double out[3]) {
    double tr = r[0] + r[4] + r[8];
    double cos_theta = (tr - 1.0) / 2.0;
    if (cos_theta > 1.0) cos_theta = 1.0;
    if (cos_theta < 0.5) return 0;  /* beyond 60 degrees in 1 ms: leave it to pinocchio */
    double theta = acos(cos_theta);
    double t = theta < 1e-4 ? 0.5 + theta * theta / 12.0 : theta / (2.0 * sin(theta));
    out[0] = t * (r[7] - r[5]);
    out[1] = t * (r[2] - r[6]);
    out[2] = t * (r[3] - r[1]);
    return 1;
}

static void quaternion_matrix(const double *quat, double r[9]) {
    double x = quat[0], y = quat[1], z = quat[2], w = quat[3];
    r[0] = 1 - 2 * (y * y + z * z); r[1] = 2 * (x * y - z * w);     r[2] = 2 * (x * z + y * w);
    r[3] = 2 * (x * y + z * w);     r[4] = 1 - 2 * (x * x + z * z); r[5] = 2 * (y * z - x * w);
    r[6] = 2 * (x * z - y * w);     r[7] = 2 * (y * z + x * w);     r[8] = 1 - 2 * (x * x + y * y);
}

/* JointMotion.step's common case: 1 and the joints moved, or 0 and nothing changed. */
static int joint_step(const double *k, double *js, const double *c, const double *position,
                      const double *quat, double dt) {
    Placement tool;
    double jac[6][7], system[7][7], rhs[7][2], target[9], rel[9], turn[3];
    const double *q = js + J_Q;
    kinematics(k, q, &tool, jac);
    for (int r = 0; r < 6; r++) for (int col = 0; col < 7; col++) system[r][col] = jac[r][col];
    for (int col = 0; col < 7; col++) system[6][col] = 0.0;
    system[6][(int)k[K_ELBOW]] = 1.0;
    quaternion_matrix(quat, target);
    for (int i = 0; i < 3; i++) {  /* target @ current.T */
        for (int j = 0; j < 3; j++) {
            rel[3 * i + j] = target[3 * i] * tool.r[3 * j] + target[3 * i + 1] * tool.r[3 * j + 1]
                             + target[3 * i + 2] * tool.r[3 * j + 2];
        }
    }
    if (!log3(rel, turn)) return 0;
    for (int r = 0; r < 6; r++) rhs[r][0] = c[r];
    rhs[6][0] = 0.0;
    for (int r = 0; r < 3; r++) {
        rhs[r][1] = (position[r] - tool.p[r]) / dt;
        rhs[3 + r][1] = turn[r] / dt;
    }
    rhs[6][1] = 0.0;
    if (!solve7(system, rhs)) return 0;
    double cdq[7], acc[7], next[7];
    for (int i = 0; i < 7; i++) {
        cdq[i] = rhs[i][0];
        acc[i] = (cdq[i] - js[J_COMMANDED + i]) / dt;
        double jerk = (acc[i] - js[J_ACCEL + i]) / dt;
        next[i] = q[i] + rhs[i][1] * dt;
        if (!(next[i] >= k[K_LOW + i] && next[i] <= k[K_HIGH + i] && fabs(cdq[i]) <= k[K_VMAX + i]
              && fabs(acc[i]) <= k[K_AMAX + i] && fabs(jerk) <= k[K_JMAX + i])) {
            return 0;
        }
    }
    for (int i = 0; i < 7; i++) {
        js[J_COMMANDED + i] = cdq[i];
        js[J_ACCEL + i] = acc[i];
        js[J_VELOCITY + i] = rhs[i][1];
        js[J_Q + i] = next[i];
    }
    return 1;
}

static int joints_at_rest(const double *js) {
    for (int i = 0; i < 7; i++) {
        if (js[J_COMMANDED + i] != 0.0 || js[J_ACCEL + i] != 0.0) return 0;
    }
    return 1;
}

/* One common cycle at time t; 0 (state unchanged) when Python must run it. */
static int cycle(double *s, const double *p, double *js, const double *k, double t) {
    double dt = p[P_DT];
    double c[6], a[6], jk[6];
    if (!isnan(s[S_HELD_TIME]) && t - s[S_HELD_TIME] > p[P_TIMEOUT]) return 0;  /* the timeout begins */
    if (p[P_INTERPOLATE] != 0.0 && t - s[S_RAMP_START] < s[S_RAMP_S]) {
        double x = (t - s[S_RAMP_START]) / s[S_RAMP_S];
        double f = x > 0.0 ? x : 0.0;
        for (int i = 0; i < 6; i++) c[i] = s[S_RAMP_FROM + i] + f * (s[S_HELD + i] - s[S_RAMP_FROM + i]);
    } else {
        for (int i = 0; i < 6; i++) c[i] = s[S_HELD + i];
    }
    for (int i = 0; i < 6; i++) {
        a[i] = (c[i] - s[S_COMMANDED + i]) / dt;
        jk[i] = (a[i] - s[S_ACCEL + i]) / dt;
    }
    const double *b = p + P_BOUNDS;
    if (!(sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]) <= b[0])
        || !(sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]) <= b[1])
        || !(sqrt(jk[0] * jk[0] + jk[1] * jk[1] + jk[2] * jk[2]) <= b[2])
        || !(sqrt(c[3] * c[3] + c[4] * c[4] + c[5] * c[5]) <= b[3])
        || !(sqrt(a[3] * a[3] + a[4] * a[4] + a[5] * a[5]) <= b[4])
        || !(sqrt(jk[3] * jk[3] + jk[4] * jk[4] + jk[5] * jk[5]) <= b[5])) {
        return 0;  /* a reflex */
    }
    /* the position, inside the workspace box (a new contact is an event: Python's) */
    double pos[3], v[3], wall[6];
    int any_wall = 0;
    for (int i = 0; i < 6; i++) { wall[i] = s[S_WALL + i]; if (wall[i] != 0.0) any_wall = 1; }
    int outside = 0;
    for (int i = 0; i < 3; i++) {
        pos[i] = s[S_POS + i] + c[i] * dt;
        v[i] = c[i];
        if (pos[i] < p[P_LO + i] || pos[i] > p[P_HI + i]) outside = 1;
    }
    if (outside || any_wall) {
        for (int i = 0; i < 3; i++) {  /* SimArm._clamp, axis by axis */
            double lo = p[P_LO + i], hi = p[P_HI + i], old = s[S_POS + i];
            if (pos[i] < lo) {
                if (wall[2 * i] == 0.0) return 0;
                v[i] = (lo - old) / dt;
                pos[i] = lo;
                continue;
            }
            wall[2 * i] = 0.0;
            if (pos[i] > hi) {
                if (wall[2 * i + 1] == 0.0) return 0;
                v[i] = (hi - old) / dt;
                pos[i] = hi;
                continue;
            }
            wall[2 * i + 1] = 0.0;
        }
    }
    /* the orientation: q <- exp(w dt / 2) (x) q, w in the base frame */
    double quat[4] = {s[S_QUAT], s[S_QUAT + 1], s[S_QUAT + 2], s[S_QUAT + 3]};
    double w = sqrt(c[3] * c[3] + c[4] * c[4] + c[5] * c[5]);
    if (w > 0.0) {
        double half = 0.5 * w * dt;
        double sn = sin(half) / w, cw = cos(half);
        double dx = c[3] * sn, dy = c[4] * sn, dz = c[5] * sn;
        double qx = quat[0], qy = quat[1], qz = quat[2], qw = quat[3];
        double rx = cw * qx + qw * dx + (dy * qz - dz * qy);
        double ry = cw * qy + qw * dy + (dz * qx - dx * qz);
        double rz = cw * qz + qw * dz + (dx * qy - dy * qx);
        double rw = cw * qw - (dx * qx + dy * qy + dz * qz);
        double n = sqrt(rx * rx + ry * ry + rz * rz + rw * rw);
        quat[0] = rx / n; quat[1] = ry / n; quat[2] = rz / n; quat[3] = rw / n;
    }
    if (p[P_JOINTS] != 0.0) {
        int moving = 0;
        for (int i = 0; i < 6; i++) if (c[i] != 0.0) moving = 1;
        if ((moving || !joints_at_rest(js)) && !joint_step(k, js, c, pos, quat, dt)) return 0;
    }
    s[S_TIME] = t;
    for (int i = 0; i < 6; i++) {
        s[S_COMMANDED + i] = c[i];
        s[S_ACCEL + i] = a[i];
        s[S_WALL + i] = wall[i];
    }
    for (int i = 0; i < 3; i++) {
        s[S_POS + i] = pos[i];
        s[S_VELOCITY + i] = v[i];
        s[S_VELOCITY + 3 + i] = c[3 + i];
    }
    for (int i = 0; i < 4; i++) s[S_QUAT + i] = quat[i];
    return 1;
}

/* Run cycles first..last at t0 + k dt; after each, the position (3) and velocity (6) go to trace
   (9 per cycle, from trace[0]). Returns the first cycle Python must run, or last + 1. */
int hri_arm_run(double *s, const double *p, double *js, const double *k, double t0, int first, int last,
                double *trace) {
    double dt = p[P_DT];
    for (int n = first; n <= last; n++) {
        if (!cycle(s, p, js, k, t0 + n * dt)) return n;
        if (trace) {
            double *row = trace + 9 * (n - first);
            for (int i = 0; i < 3; i++) row[i] = s[S_POS + i];
            for (int i = 0; i < 6; i++) row[3 + i] = s[S_VELOCITY + i];
        }
    }
    return last + 1;
}

/* The layout sizes, so the loader can refuse a library built from another version of this file. */
int hri_arm_layout(int which) {
    switch (which) {
        case 0: return S_SIZE;
        case 1: return P_SIZE;
        case 2: return J_SIZE;
        case 3: return K_SIZE;
        default: return -1;
    }
}

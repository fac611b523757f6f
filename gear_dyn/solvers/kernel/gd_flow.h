/* gear_dyn flow kernel: the sequential loops of the solvers, on affine maps that Python computes
 * (gd_flow.c). A map of an n-state linear model is y -> F y + h with F n x n (row-major) and h
 * of length n; arrays of maps are contiguous, map j at F + j n^2, h + j n. C99, libm only; no
 * global state, so calls from several threads at once are safe. */
#ifndef GD_FLOW_H
#define GD_FLOW_H

/* the version of this interface (gear_dyn.solvers.kernel checks it on load) */
#define GD_FLOW_VERSION 5

int gd_flow_version(void);

/* largest |t[i] - (t0 + i dt)| over i = 0..n-1: how far a grid is from a uniform one (s) */
double gd_flow_grid_error(long n, const double *t, double t0, double dt);

/* partial products of count maps: Q[0] = I, R[0] = 0, Q[j+1] = F[j] Q[j],
 * R[j+1] = F[j] R[j] + h[j], j = 0..count-1 (Q: (count+1) n^2, R: (count+1) n) */
void gd_flow_products(int n, long count, const double *F, const double *h, double *Q,
                      double *R);

/* maps of n_steps steps, each the product of its parts in time order: parts[i] ((n+1) x (n+1),
 * augmented: the affine map [[F, h], [0, 1]]) is the next part of step owner[i]; owner is
 * non-decreasing, in 0..n_steps-1 (total: n_steps (n+1)^2; a step without parts: identity) */
void gd_flow_compose(int n, long n_parts, const double *parts, const long *owner, long n_steps,
                     double *total);

/* states at the map boundaries: Y[0] = y0, Y[j+1] = F[j] Y[j] + h[j] (Y: (count+1) n) */
void gd_flow_chain(int n, long count, const double *F, const double *h, const double *y0,
                   double *Y);

/* states on a uniform grid of n_samples points, s_per per period, from y0 and the partial
 * products (Q, R) of one period's step maps (gd_flow_products; s_used + 1 of them, s_used =
 * min(s_per, n_samples - 1)): sample k s_per + j is Q[j] y_k + R[j], where y_k, the state at
 * the k-th period start, is Q[s_per] y_{k-1} + R[s_per]. out is n x n_samples (row-major:
 * state i at out + i n_samples). Returns 0, or 1 when a state is not finite (a diverging
 * response; out is then NaN from that sample on). */
int gd_flow_fill_periodic(int n, long s_per, long n_samples, const double *Q, const double *R,
                          const double *y0, double *out);

/* ---- the contact walk: the single-DOF model with backlash, exactly (gear_dyn.solvers.
 * contact_exact). m u'' + c u' + k f(u) = W + sum_n (forcing harmonics), f the dead zone of
 * half gap b, in u = x - e(t); linear with constant coefficients in each contact state
 * (state -1 back flank, 0 gap, +1 drive flank) of each stiffness piece. Python exports:
 *   model  [GD_CW_MODEL + 2 nh]: m (kg), c (N s/m), w (N), b (m), fm (Hz), p0 (cycles), nh,
 *          then tn[nh] = 2 pi n (rad per cycle) and om[nh] = 2 pi n fm (rad/s);
 *   pieces [n_pieces (GD_CW_ROW + 2 nh)], one row per contact state and stiffness value:
 *          state, k (N/m), a = c/m (1/s), w2 = k/m (1/s^2, 0 in the gap), q (damped rad/s,
 *          0: none), x_eq (m), h (sampling step, s; inf: none), amp (bound of |u_p|, m),
 *          curv (bound of |u_p''|, m/s^2), then the particular solution's ca[nh], cb[nh] (m):
 *          u_p(t) = sum_n ca cos(tn p) + cb sin(tn p), p = fmod(fm t + p0, 1).
 * Row 3 j + state + 1 is contact state `state` of stiffness value j. */
#define GD_CW_MODEL 7
#define GD_CW_ROW 9

/* status codes of gd_contact_walk */
#define GD_CW_OK 0
#define GD_CW_FULL 1      /* more segments than cap: call again with a larger one */
#define GD_CW_CHATTER 2   /* more than max_events contact changes in one stiffness piece */
#define GD_CW_GRAZE 3     /* a discontinuous field crossed tangentially: walked, phi NaN */

/* closed form x(s), v(s) of one contact state from (x0, v0) at s = 0, at n times s */
void gd_contact_flow(int state, double k, double m, double c, double w, double b, double x0,
                     double v0, long n, const double *s, double *x, double *v);

/* a root of f in [lo, hi] (f_lo, f_hi of opposite signs) to xtol: Illinois false position
 * safeguarded by bisection (the kernel's bracketing root finder, exported for tests; the contact
 * walk closes its contact changes with Newton steps, having the slope too) */
double gd_find_root(double (*f)(double, void *), void *ctx, double lo, double hi, double f_lo,
                    double f_hi, double xtol);

/* 1 when the motion of piece `piece` from (u0, v0) at t0 provably never leaves its state */
int gd_contact_stays_inside(const double *model, const double *pieces, long piece, double u0,
                            double v0, double t0);

/* time after t0 of the first contact change of piece `piece` from (u0, v0) at t0 within
 * length (s), in *hit; returns 1 if there is one, else 0 */
int gd_contact_first_crossing(const double *model, const double *pieces, long piece, double t0,
                              double u0, double v0, double length, double xtol, double *hit);

/* the walk from (u0, v0) at cuts[0] to cuts[n_cuts]: stiffness piece i spans cuts[i] ..
 * cuts[i+1] with stiffness value kidx[i]. Records each closed-form segment in seg (4 per
 * segment: start time, u, u' at the start, duration) and seg_id (2 per segment: piece row,
 * 1 if it ends at a contact change), up to cap segments, their number in *n_seg; out[0..1]
 * the end state, out[2..5] the sensitivity d y(end) / d y(start) (row-major), out[6] the time
 * of a failure. With slot and phis (else NULL), slot[i] (non-decreasing) names the slot of
 * piece i and phis (4 per slot, identities on entry) receives the sensitivity over each
 * slot's pieces (e.g. one slot per mesh period). With rates and dpar (else NULL), the
 * derivative of the end state with respect to a parameter p: rates[n_cuts + 1] the cuts'
 * d t / d p (s per unit of p; a stiffness switch or an end that moves with p), dpar[3] on
 * entry d (u0, u0') / d p and d fm / d p, on exit d (u, u')(end) / d p; dpieces
 * [n_pieces 2 nh] (NULL without harmonics) the derivatives d ca / d p, d cb / d p of each
 * row's particular solution. Returns a GD_CW_ status. */
int gd_contact_walk(const double *model, const double *pieces, long n_cuts, const double *cuts,
                    const long *kidx, double u0, double v0, double xtol, long max_events,
                    long cap, double *seg, long *seg_id, long *n_seg, double *out,
                    const long *slot, double *phis, const double *rates,
                    const double *dpieces, double *dpar);

/* u, u' at n_t times t (inside the walked span) from n_seg segments of gd_contact_walk (in
 * time order), each from the closed form of the segment it falls in; out is 2 x n_t
 * (row-major). Returns 1 when a state is not finite, else 0. */
int gd_contact_on_grid(const double *model, const double *pieces, long n_seg, const double *seg,
                       const long *seg_id, long n_t, const double *t, double *out);

/* ---- the linear single-DOF model over many speeds at once (gd_linear.c; gear_dyn.solvers.
 * linear_maps): x'' = -kappa(p) x - gamma x' + g0(p) + fm g1(p), p the mesh phase, fm the mesh
 * frequency (Hz). One mesh period is cut into n_steps steps, each a row of GD_LIN_ROW values
 * in phase, shared by every speed (lane) that uses its table:
 *   length (cycles), kappa_a, kappa_b (1/s^2), gamma (1/s), g0_a, g0_b (m/s^2),
 *   g1_a, g1_b (m/s), the coefficients at the step's two Gauss points a, b.
 * At fm the step (h = length / fm) is y -> E y + q, the exponential of the augmented generator
 * [[B, f], [0, 0]] of the fourth-order Magnus step with two Gauss points (Blanes, Casas, Oteo
 * & Ros 2009, eq. 4.6), B = h/2 (A_a + A_b) + sqrt(3)/12 h^2 [A_b, A_a]: exact where the
 * coefficients are constant in the step (kappa_a = kappa_b, ...). E = exp(B) in closed form,
 * q = (I - E) y* with y* = -B^-1 f (q = f where B is singular). rows holds the tables one after
 * the other (n_steps rows each); table[lane] names a lane's table (NULL: table 0 for all). */
#define GD_LIN_ROW 8

/* E[i] = exp(B[i]) of n 2x2 matrices (row-major, 4 values each), in closed form */
void gd_lin_expm2(long n, const double *B, double *E);

/* every step's map of every lane: F (n_lanes n_steps 4), h (n_lanes n_steps 2) */
void gd_lin_maps(long n_lanes, long n_steps, const double *rows, const long *table,
                 const double *fm, double *F, double *h);

/* the partial products y_i = P_i y_0 + u_i of every lane's steps after the steps keep[k]
 * (increasing, in 0..n_steps-1): Q (n_lanes n_keep 4) holds P, R (n_lanes n_keep 2) holds u */
void gd_lin_period(long n_lanes, long n_steps, const double *rows, const long *table,
                   const double *fm, long n_keep, const long *keep, double *Q, double *R);

/* the responses from rest of n_lanes offset sequences to one sequence of 2x2 maps: lane s
 * from Y[s, 0] = 0, Y[s, i+1] = F[i] Y[s, i] + h[s, i] (F: n_steps 4, shared by the lanes;
 * h: n_lanes n_steps 2; Y: n_lanes (n_steps + 1) 2) */
void gd_lin_chain(long n_lanes, long n_steps, const double *F, const double *h, double *Y);

#endif

/* gear_dyn flow kernel: the sequential loops of the solvers, on affine maps that Python computes
 * (gd_flow.c). A map of an n-state linear model is y -> F y + h with F n x n (row-major) and h
 * of length n; arrays of maps are contiguous, map j at F + j n^2, h + j n. C99, libm only; no
 * global state, so calls from several threads at once are safe. */
#ifndef GD_FLOW_H
#define GD_FLOW_H

/* the version of this interface (gear_dyn.solvers.kernel checks it on load) */
#define GD_FLOW_VERSION 4

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

#endif

/* The three sweeps over all DOFs of one time step of the batch simulator, in C.

   Compiled by presag_opt.native.sweeps and called from the numba kernel's one driver loop
   (presag_opt.dynamics.batch.kernel.advance) in place of its own sweeps. Each function does exactly
   the IEEE operations of its numba counterpart in kernel.py, in the same order, so both give the
   same numbers to the last bit (compiled with -ffp-contract=off and without fast-math). What differs
   is how the runs are held: the numba loops keep one accumulator per run in memory, whose
   load-add-store chain costs about 15 cycles per band entry whatever the number of runs; here the
   runs are processed in blocks of LANES (one or two blocks per pass) whose accumulators the compiler
   keeps in vector registers (plain loops over a block of fixed length, which GCC and Clang vectorise;
   an inlined helper with the block count as a parameter was three times slower with GCC 12).

   Arrays are C-ordered. Run arrays have a leading dimension `ld`, a multiple of LANES; lanes beyond
   the active runs are computed too (their runs have finished or do not exist) and never read as
   results. Band storage by rows: band[j, k] = A[j + k, j], `width` = bandwidth + 1; the diagonals
   are read from the bands, the off-diagonal entries from their nonzero lists by rows
   (presag_opt.dynamics.batch.band_rows: row j's entries are start[j] .. start[j + 1] - 1, with their
   columns and values), in the order a full-band sweep would add them. */

#include <math.h>
#include <stdint.h>

#define LANES 8
#define PHI_ROWS 64 /* rows per block of sweep 3: its slice of the run arrays stays in the L1 cache */
#define STATUS_RUNNING (-1)

/* numba's max(acc, value): value if value > acc, else acc (Python's rule, NaN included). */
static inline double python_max(double acc, double value) { return value > acc ? value : acc; }

static inline int64_t min64(int64_t a, int64_t b) { return a < b ? a : b; }

/* g = r - s lin of one lane on a row: kept on a candidate row (c >= 0), else folded into the force
   scale and the residual at the predictor. Returns g. */
static inline double right_hand_side(double lin, double rj, double s, int64_t c, int64_t lane, int64_t ld,
                                     double *restrict g, double *restrict scale, double *restrict first_residual)
{
    const double gj = rj - s * lin;
    if (c >= 0) {
        g[c * ld + lane] = gj;
    } else {
        double largest = scale[lane];
        largest = python_max(largest, fabs(s * lin));
        largest = python_max(largest, fabs(rj));
        scale[lane] = largest;
        first_residual[lane] = python_max(first_residual[lane], fabs(gj));
    }
    return gj;
}

/* Sweep 1: C v + K u = alpha_R M v + K q row by row (kept on every row), g = r - s (C v + K u), the force scale and
   residual on rows no nonlinear force reaches, and the forward substitution of K_eff delta = g;
   one or two blocks of lanes per pass. K's off-diagonal entries are k_start/k_column/k_value, the
   factor's left of its diagonal l_start/l_column/l_value. */
void presag_forward_sweep(
    const double *restrict stiffness, const double *restrict factor, const double *restrict mass,
    int64_t n, int64_t width, const int64_t *restrict k_start, const int64_t *restrict k_column,
    const double *restrict k_value, const int64_t *restrict l_start, const int64_t *restrict l_column,
    const double *restrict l_value, double rayleigh_alpha, double s, const double *restrict q,
    const double *restrict v, const double *restrict r, const int64_t *restrict candidate,
    double *restrict linear, double *restrict g, double *restrict scale, double *restrict first_residual,
    double *restrict delta, int64_t ld, int64_t lanes)
{
    for (int64_t b0 = 0; b0 < lanes; b0 += 2 * LANES) {
        const int two = b0 + LANES < lanes;
        for (int64_t j = 0; j < n; j++) {
            double a[LANES], c[LANES];
            const double d = stiffness[j * width];
            const double m = rayleigh_alpha * mass[j];
            const int64_t row = j * ld + b0;
            for (int i = 0; i < LANES; i++) {
                a[i] = d * q[row + i] + m * v[row + i];
                c[i] = two ? d * q[row + LANES + i] + m * v[row + LANES + i] : 0.0;
            }
            for (int64_t e = k_start[j]; e < k_start[j + 1]; e++) {
                const double value = k_value[e];
                const double *qk = q + k_column[e] * ld + b0;
                for (int i = 0; i < LANES; i++) a[i] += value * qk[i];
                if (two)
                    for (int i = 0; i < LANES; i++) c[i] += value * qk[LANES + i];
            }
            for (int i = 0; i < LANES; i++) linear[row + i] = a[i];
            if (two)
                for (int i = 0; i < LANES; i++) linear[row + LANES + i] = c[i];
            const int64_t cand = candidate[j];
            for (int i = 0; i < LANES; i++)
                a[i] = right_hand_side(a[i], r[row + i], s, cand, b0 + i, ld, g, scale, first_residual);
            if (two)
                for (int i = 0; i < LANES; i++)
                    c[i] = right_hand_side(c[i], r[row + LANES + i], s, cand, b0 + LANES + i, ld, g, scale,
                                           first_residual);
            for (int64_t e = l_start[j]; e < l_start[j + 1]; e++) {
                const double value = l_value[e];
                const double *dk = delta + l_column[e] * ld + b0;
                for (int i = 0; i < LANES; i++) a[i] -= value * dk[i];
                if (two)
                    for (int i = 0; i < LANES; i++) c[i] -= value * dk[LANES + i];
            }
            const double pivot = factor[j * width];
            for (int i = 0; i < LANES; i++) delta[row + i] = a[i] / pivot;
            if (two)
                for (int i = 0; i < LANES; i++) delta[row + LANES + i] = c[i] / pivot;
        }
    }
}

/* Sweep 2: backward substitution L^T x = y in place, one or two blocks of lanes per pass; the
   entries of L^T right of its diagonal are u_start/u_column/u_value. */
void presag_backward_sweep(const double *restrict factor, const int64_t *restrict u_start,
                           const int64_t *restrict u_column, const double *restrict u_value, double *restrict x,
                           int64_t n, int64_t width, int64_t ld, int64_t lanes)
{
    for (int64_t b0 = 0; b0 < lanes; b0 += 2 * LANES) {
        const int two = b0 + LANES < lanes;
        for (int64_t j = n - 1; j >= 0; j--) {
            double a[LANES], c[LANES];
            double *xj = x + j * ld + b0;
            for (int i = 0; i < LANES; i++) {
                a[i] = xj[i];
                c[i] = two ? xj[LANES + i] : 0.0;
            }
            for (int64_t e = u_start[j]; e < u_start[j + 1]; e++) {
                const double value = u_value[e];
                const double *xk = x + u_column[e] * ld + b0;
                for (int i = 0; i < LANES; i++) a[i] -= value * xk[i];
                if (two)
                    for (int i = 0; i < LANES; i++) c[i] -= value * xk[LANES + i];
            }
            const double pivot = factor[j * width];
            for (int i = 0; i < LANES; i++) xj[i] = a[i] / pivot;
            if (two)
                for (int i = 0; i < LANES; i++) xj[LANES + i] = c[i] / pivot;
        }
    }
}

/* Sweep 3: delta = delta_lin - s Z phi, the new state and the next step's predictors, and the
   support uplift of the runs still going; by blocks of PHI_ROWS rows: each run's few terms of Z phi
   along the block (a column of Z is contiguous), then the block's state, the runs innermost. */
void presag_update_sweep(
    int64_t n, const double *restrict mass, const double *restrict columns, const int64_t *restrict phi_count,
    const int64_t *restrict phi_column, const double *restrict phi_coefficient, int64_t phi_size,
    double *restrict u, double *restrict v, double *restrict q, double *restrict r, double *restrict delta,
    int64_t ld, int64_t lanes, int64_t active, double a0, double c_g, double dt, double c_a, double c_v, double s,
    double hht_alpha, double rayleigh_beta, const uint8_t *restrict support_row, const int64_t *restrict status,
    const int64_t *restrict n_steps, int64_t step, double *restrict uplift_max)
{
    for (int64_t j0 = 0; j0 < n; j0 += PHI_ROWS) {
        const int64_t j1 = min64(n, j0 + PHI_ROWS);
        for (int64_t b = 0; b < active; b++) {
            const int64_t count = phi_count[b];
            for (int64_t k = 0; k < count; k++) {
                const double coefficient = phi_coefficient[b * phi_size + k];
                const double *restrict column = columns + phi_column[b * phi_size + k] * n;
                for (int64_t j = j0; j < j1; j++) delta[j * ld + b] -= coefficient * column[j];
            }
        }
        for (int64_t j = j0; j < j1; j++) {
            const int64_t row = j * ld;
            const double m = mass[j];
            for (int64_t b = 0; b < lanes; b++) {
                const double dj = delta[row + b];
                const double aj = a0 * dj;
                const double uj = u[row + b] + dj;
                const double vj = v[row + b] + c_g * aj;
                const double rj = (r[row + b] - m * aj) / s;
                const double up = uj + dt * vj + c_a * aj;
                const double vp = vj + c_v * aj;
                delta[row + b] = uj;
                u[row + b] = up;
                v[row + b] = vp;
                q[row + b] = up + rayleigh_beta * vp;
                r[row + b] = hht_alpha * rj;
            }
            if (support_row[j]) {
                for (int64_t b = 0; b < active; b++)
                    if (status[b] == STATUS_RUNNING && n_steps[b] >= step)
                        uplift_max[b] = python_max(uplift_max[b], delta[row + b]);
            }
        }
    }
}

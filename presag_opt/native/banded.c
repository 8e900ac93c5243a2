/* Banded Cholesky solve with many right-hand sides, in C.

   Built by presag_opt.native.compiler and called from presag_opt.native.banded (the "compiled"
   back-end) in place of its numba twin presag_opt.native.banded_numba.banded_cholesky_solve: the
   same operations in the same order (compiled with -ffp-contract=off, no fast-math), so the same
   numbers to the last bit, without importing numba (about half a second of a command's start).

   factor: the Cholesky factor by rows, factor[j, k] = L[j + k, j], shape (n, width), C order.
   x: right-hand sides, shape (n, ld), C order; its first `columns` columns are overwritten by the
   solution of L L^T y = x. `acc` is scratch of `columns` doubles. */

#include <stdint.h>

void presag_banded_cholesky_solve(const double *restrict factor, double *restrict x, double *restrict acc,
                                  int64_t n, int64_t width, int64_t ld, int64_t columns)
{
    const int64_t bw = width - 1;
    for (int64_t j = 0; j < n; j++) {
        for (int64_t b = 0; b < columns; b++) acc[b] = x[j * ld + b];
        const int64_t down = bw < j ? bw : j;
        for (int64_t k = 1; k <= down; k++) {
            const double value = factor[(j - k) * width + k];
            const double *xk = x + (j - k) * ld;
            for (int64_t b = 0; b < columns; b++) acc[b] -= value * xk[b];
        }
        const double pivot = factor[j * width];
        for (int64_t b = 0; b < columns; b++) x[j * ld + b] = acc[b] / pivot;
    }
    for (int64_t j = n - 1; j >= 0; j--) {
        for (int64_t b = 0; b < columns; b++) acc[b] = x[j * ld + b];
        const int64_t up = bw < n - 1 - j ? bw : n - 1 - j;
        for (int64_t k = 1; k <= up; k++) {
            const double value = factor[j * width + k];
            const double *xk = x + (j + k) * ld;
            for (int64_t b = 0; b < columns; b++) acc[b] -= value * xk[b];
        }
        const double pivot = factor[j * width];
        for (int64_t b = 0; b < columns; b++) x[j * ld + b] = acc[b] / pivot;
    }
}

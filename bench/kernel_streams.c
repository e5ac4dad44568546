/* The shape of flexbody's block solve kernel (linalg::supernodal) on
 * synthetic data: 7.4e7 entries of L in blocks of M rows by W columns,
 * four columns at a time, each row broadcast into 8 right-hand sides (one
 * cache line, from a small hot array). It shows how fast four short
 * column-major streams can be read, with and without a prefetch of the
 * next four columns, and from four columns stored interleaved row by row.
 *
 *   gcc -O3 -march=native -fopenmp bench/kernel_streams.c -o /tmp/kernel_streams
 *   OMP_NUM_THREADS=2 /tmp/kernel_streams 100 16   # M W
 *
 * Prints GB/s of L read and entries per cycle and core (at 2.25 GHz). */
#include <immintrin.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>

enum layout { COLUMNS, COLUMNS_PREFETCH, PANELS };

static double run(const double *L, size_t nb, int m, int w, enum layout how) {
    static double y[1024 * 8];
    for (int i = 0; i < 1024 * 8; i++) y[i] = 1.0;
    size_t blk = (size_t)m * w;
    double out = 0;
#pragma omp parallel for reduction(+ : out) schedule(static)
    for (size_t b = 0; b < nb; b++) {
        const double *B = L + b * blk;
        for (int j = 0; j + 4 <= w; j += 4) {
            __m256d a[8];
            for (int k = 0; k < 8; k++) a[k] = _mm256_setzero_pd();
            for (int p = 0; p < m; p++) {
                if (how == COLUMNS_PREFETCH && (p & 7) == 0 && j + 8 <= w)
                    for (int c = 0; c < 4; c++)
                        _mm_prefetch((const char *)(B + (size_t)(j + 4 + c) * m + p), _MM_HINT_T0);
                const double *yr = y + ((p * 37) & 1023) * 8;
                __m256d y0 = _mm256_loadu_pd(yr), y1 = _mm256_loadu_pd(yr + 4);
                double l[4];
                for (int c = 0; c < 4; c++)
                    l[c] = how == PANELS ? B[(size_t)j * m + 4 * p + c] : B[(size_t)(j + c) * m + p];
                for (int c = 0; c < 4; c++) {
                    __m256d s = _mm256_set1_pd(l[c]);
                    a[2 * c] = _mm256_fmadd_pd(s, y0, a[2 * c]);
                    a[2 * c + 1] = _mm256_fmadd_pd(s, y1, a[2 * c + 1]);
                }
            }
            double r[4];
            for (int k = 1; k < 8; k++) a[0] = _mm256_add_pd(a[0], a[k]);
            _mm256_storeu_pd(r, a[0]);
            out += r[0] + r[1] + r[2] + r[3];
        }
    }
    return out;
}

int main(int argc, char **argv) {
    int m = argc > 1 ? atoi(argv[1]) : 100, w = argc > 2 ? atoi(argv[2]) : 16;
    size_t blk = (size_t)m * w, nb = 74000000 / blk;
    double *L = aligned_alloc(64, nb * blk * sizeof(double));
    for (size_t i = 0; i < nb * blk; i++) L[i] = 1e-9 * (double)(i % 1000);
    const char *names[] = {"column-major", "column-major + prefetch", "interleaved panels"};
    for (int how = COLUMNS; how <= PANELS; how++) {
        double best = 1e30, check = 0;
        for (int rep = 0; rep < 4; rep++) {
            double t = omp_get_wtime();
            check = run(L, nb, m, w, how);
            t = omp_get_wtime() - t;
            if (rep > 0 && t < best) best = t;
        }
        printf("M=%d W=%d %-24s %.4f s %5.1f GB/s %.2f entries/cycle/core (%g)\n", m, w,
               names[how], best, nb * blk * 8 / best / 1e9, nb * blk / best / 2 / 2.25e9, check);
    }
    free(L);
    return 0;
}

/* Prints points of GSL's base-2 Niederreiter generator (gsl_qrng_niederreiter_2) as
 * golden test data for crates/qmc/tests/digital_niederreiter.rs.
 * It links GSL (GPL) only to print test data; no GSL code is used in the project.
 * Build and run:  gcc -O2 sobol_niederreiter_gsl.c -lgsl -lgslcblas -lm -o /tmp/nied && /tmp/nied 12 300
 * Output: one point per line, coordinates as exact integers x·2^31 (GSL uses 31 bits). */
#include <stdio.h>
#include <stdlib.h>
#include <gsl/gsl_qrng.h>

int main(int argc, char **argv) {
    unsigned dimensions = argc > 1 ? (unsigned)atoi(argv[1]) : 12;
    unsigned count = argc > 2 ? (unsigned)atoi(argv[2]) : 64;
    gsl_qrng *generator = gsl_qrng_alloc(gsl_qrng_niederreiter_2, dimensions);
    double point[12];
    for (unsigned index = 0; index < count; ++index) {
        gsl_qrng_get(generator, point);
        for (unsigned dimension = 0; dimension < dimensions; ++dimension)
            printf("%s%.0f", dimension ? " " : "", point[dimension] * 2147483648.0);
        printf("\n");
    }
    gsl_qrng_free(generator);
    return 0;
}

/* The Abaqus utility routines a UMAT may call, as the small shared library
 * libstratum_umat_utilities.so that the umat adapter links and makes global before it opens a
 * UMAT, so that a UMAT's undefined references to them resolve at load time. Our own
 * implementations from the documented argument conventions (README.md, "Utility routines"):
 *
 *   XIT()                                   end the analysis (the adapter stops the run)
 *   SINV(STRESS, SINV1, SINV2, NDI, NSHR)   SINV1 = trace / 3, SINV2 = Mises equivalent
 *   SPRINC(S, PS, LSTR, NDI, NSHR)          principal values PS(3)
 *   SPRIND(S, PS, AN, LSTR, NDI, NSHR)      principal values and directions AN(3, 3)
 *   ROTSIG(S, R, SPRIME, LSTR, NDI, NSHR)   SPRIME = R S R^T
 *
 * Every argument by reference (Fortran); the Fortran names of gfortran (lower case, trailing
 * underscore). S holds NDI direct components (11, 22, 33) and NSHR shears (12, 13, 23) as a
 * UMAT's STRESS or STRAN does; LSTR = 1: a stress (tensor shears), LSTR = 2: a strain
 * (engineering shears, halved to form the tensor). */
#ifndef STRATUM_ABAQUS_UTILITIES_H
#define STRATUM_ABAQUS_UTILITIES_H

#ifdef __cplusplus
extern "C" {
#endif

void xit_(void);
void sinv_(const double* stress, double* sinv1, double* sinv2, const int* ndi, const int* nshr);
void sprinc_(const double* s, double* ps, const int* lstr, const int* ndi, const int* nshr);
void sprind_(const double* s, double* ps, double* an, const int* lstr, const int* ndi, const int* nshr);
void rotsig_(const double* s, const double* r, double* sprime, const int* lstr, const int* ndi,
             const int* nshr);

/* Calls fn(arg) with an XIT target set for this thread: returns 0 when fn returned, 1 when the
 * code it called called XIT (fn's frames are then left by longjmp; they must hold nothing
 * that needs destruction: the UMAT's own frames and a plain trampoline). Nested calls restore
 * the outer target. */
int stratum_umat_guarded_call(void (*fn)(void*), void* arg);

#ifdef __cplusplus
}
#endif

#endif

/* Gives any program the reference binary's prefault (docs/performance.md):
 * every malloc, calloc or realloc block of 1 MiB or more (a grown block's
 * new part) is faulted in at once with madvise(MADV_POPULATE_WRITE).
 * Used to check that the gain is the reference's exact reservations, not
 * the advice alone: OpenMesh's driver gains 0-2% with it (ours 3-13%).
 *
 *   PREFAULT_CHECK=1 reference/bench/peers/run.sh builds and runs it; by hand:
 *   gcc -O2 -shared -fPIC -o target/peers/prefault_shim.so \
 *       reference/bench/peers/prefault_shim.c -ldl
 *   LD_PRELOAD=target/peers/prefault_shim.so target/peers/om_loop FILE 2
 */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <malloc.h>
#include <stddef.h>
#include <stdint.h>
#include <sys/mman.h>

#ifndef MADV_POPULATE_WRITE
#define MADV_POPULATE_WRITE 23
#endif

static void *(*next_malloc)(size_t);
static void *(*next_calloc)(size_t, size_t);
static void *(*next_realloc)(void *, size_t);

/* The whole pages of block[from, to), from the page holding block + from
 * when that page is the block's own. */
static void prefault(void *block, size_t from, size_t to) {
    const uintptr_t page = 4096;
    if (!block || to < from || to - from < ((size_t)1 << 20)) return;
    uintptr_t b = (uintptr_t)block;
    uintptr_t first = (b + page - 1) & ~(page - 1);
    uintptr_t start = (b + from) & ~(page - 1);
    if (start < first) start = first;
    uintptr_t end = (b + to) & ~(page - 1);
    if (end > start) madvise((void *)start, end - start, MADV_POPULATE_WRITE);
}

void *malloc(size_t n) {
    if (!next_malloc) next_malloc = dlsym(RTLD_NEXT, "malloc");
    void *p = next_malloc(n);
    prefault(p, 0, n);
    return p;
}

/* dlsym may call calloc before next_calloc is known: a small static
 * buffer answers that first call. */
static char early[4096];
static size_t early_used;
void *calloc(size_t k, size_t n) {
    if (!next_calloc) {
        static int resolving;
        if (resolving) {
            size_t want = (k * n + 15) & ~(size_t)15;
            if (early_used + want > sizeof early) return NULL;
            void *p = early + early_used;
            early_used += want;
            return p;
        }
        resolving = 1;
        next_calloc = dlsym(RTLD_NEXT, "calloc");
        resolving = 0;
    }
    void *p = next_calloc(k, n);
    if (p) prefault(p, 0, k * n);
    return p;
}

void *realloc(void *old, size_t n) {
    if (!next_realloc) next_realloc = dlsym(RTLD_NEXT, "realloc");
    size_t kept = old ? malloc_usable_size(old) : 0;
    void *p = next_realloc(old, n);
    prefault(p, kept < n ? kept : n, n);
    return p;
}

void free(void *p) {
    static void (*next_free)(void *);
    if ((char *)p >= early && (char *)p < early + sizeof early) return;
    if (!next_free) next_free = dlsym(RTLD_NEXT, "free");
    next_free(p);
}

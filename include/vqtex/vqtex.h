/* vqtex.h - the public C API of vqtex, a texture codec after Wei & Levoy,
 * "Fast Texture Synthesis using Tree-structured Vector Quantization"
 * (SIGGRAPH 2000).
 *
 * Conventions
 * - Every function returns a vqtex_status; VQTEX_OK is 0. When a vqtex_error
 *   pointer is given it receives the status and a one-line detail saying
 *   what went wrong, where, and what to do.
 * - Params structs are filled with defaults by their *_init function, then
 *   tweaked. The init function stamps the struct size, so a library can tell
 *   a caller built against another version of this header.
 * - Images are 8-bit, 1 to 4 channels interleaved (grey, grey+alpha, RGB,
 *   RGBA), rows packed with no padding. Images the library returns are freed
 *   with vqtex_image_free().
 * - No global state: calls on different data may run concurrently.
 * - Determinism: output bytes depend only on the inputs, the parameters and
 *   the seed; never on the thread count, the CPU's SIMD level or the run.
 */
#ifndef VQTEX_H
#define VQTEX_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#if defined(_WIN32) && defined(VQTEX_SHARED)
#define VQTEX_API __declspec(dllexport)
#elif defined(__GNUC__)
#define VQTEX_API __attribute__((visibility("default")))
#else
#define VQTEX_API
#endif

#define VQTEX_VERSION_MAJOR 0
#define VQTEX_VERSION_MINOR 1
#define VQTEX_VERSION_PATCH 0
#define VQTEX_VERSION_NUMBER \
    (VQTEX_VERSION_MAJOR * 10000 + VQTEX_VERSION_MINOR * 100 + VQTEX_VERSION_PATCH)

/* The library's version, as VQTEX_VERSION_NUMBER and as "MAJOR.MINOR.PATCH". */
VQTEX_API uint32_t vqtex_version(void);
VQTEX_API const char* vqtex_version_string(void);

/* Values never change once released. */
typedef enum vqtex_status {
    VQTEX_OK = 0,
    VQTEX_ERROR_INVALID_ARGUMENT = 1, /* a parameter or image is out of range */
    VQTEX_ERROR_IMAGE_TOO_SMALL = 2,  /* the example is smaller than the neighbourhood */
    VQTEX_ERROR_OUT_OF_MEMORY = 3,
    VQTEX_ERROR_CANCELLED = 4,        /* the progress callback returned 0 */
    VQTEX_ERROR_LIMIT_EXCEEDED = 5,   /* a size is above the configured cap */
    VQTEX_ERROR_INTERNAL = 99
} vqtex_status;

/* A static, human-readable description of a status. */
VQTEX_API const char* vqtex_status_message(vqtex_status status);

typedef struct vqtex_error {
    vqtex_status status;
    char detail[256]; /* what, where, what to do; NUL-terminated */
} vqtex_error;

typedef struct vqtex_image {
    uint32_t width;
    uint32_t height;
    uint32_t channels; /* 1 to 4 */
    uint8_t* pixels;   /* width * height * channels bytes */
} vqtex_image;

/* Frees pixels the library allocated and zeroes the struct; NULL is fine. */
VQTEX_API void vqtex_image_free(vqtex_image* image);

#define VQTEX_MAX_LEVELS 8

/* A multiresolution neighbourhood {RxC,k} (paper section 2.3): the causal
 * part of an RxC window at the current level plus full windows, about half
 * as wide per level, at the k-1 coarser levels. rows and cols are odd. */
typedef struct vqtex_shape {
    uint8_t rows;
    uint8_t cols;
    uint8_t levels;
} vqtex_shape;

typedef enum vqtex_search {
    VQTEX_SEARCH_TSVQ = 0,       /* tree-structured VQ codebooks (paper section 4) */
    VQTEX_SEARCH_EXHAUSTIVE = 1  /* every example neighbourhood: exact and slow */
} vqtex_search;

typedef enum vqtex_leaf {
    VQTEX_LEAF_MEDOID = 0,  /* leaf = a real example neighbourhood and its pixel (sharper) */
    VQTEX_LEAF_CENTROID = 1 /* leaf = cluster mean and mean pixel (blurrier) */
} vqtex_leaf;

typedef enum vqtex_init {
    /* Coarsest level from histogram-matched noise, each finer level from the
     * coarser one upsampled: fewer broken top rows and seams (default). */
    VQTEX_INIT_PARENT = 0,
    /* Every level from histogram-matched white noise, as the paper (2.5). */
    VQTEX_INIT_NOISE = 1
} vqtex_init;

typedef enum vqtex_stage {
    VQTEX_STAGE_ANALYSE = 0,   /* building the pyramid and codebooks */
    VQTEX_STAGE_SYNTHESISE = 1 /* synthesising the output */
} vqtex_stage;

/* Called from the calling thread; return 0 to cancel (the call then returns
 * VQTEX_ERROR_CANCELLED and writes no output). */
typedef int (*vqtex_progress_fn)(void* user, vqtex_stage stage, uint64_t done, uint64_t total);

/* How an example becomes a model: pyramid, neighbourhoods, codebooks.
 * Zero in any field means "the default". CLI flags in brackets. */
typedef struct vqtex_model_params {
    uint32_t levels;                          /* pyramid depth; 0 = automatic [--levels] */
    vqtex_shape shapes[VQTEX_MAX_LEVELS];     /* [0] = finest; {0,0,0} = default [--shapes] */
    uint32_t example_tileable;                /* 1: the example wraps (toroidal neighbourhoods) [--tileable-example] */
    uint32_t codewords[VQTEX_MAX_LEVELS];     /* leaves per level, [0] finest; 0 = codeword_fraction [--codewords] */
    float codeword_fraction;                  /* leaves as a fraction of the training vectors [--codewords] */
    float train_fraction;                     /* train on this fraction of the vectors (1 = all) [--train-fraction] */
    uint32_t train_count;                     /* or at most this many per level (0 = no cap) */
    vqtex_leaf leaf;                          /* [--leaf] */
    float distortion_threshold;               /* stop splitting at this mean SSD per vector (0 = off) */
    uint64_t training_seed;                   /* seeds the training subset */
    uint32_t entries_per_leaf;                /* outputs per TSVQ leaf, 1 to 64 (0 = default) [--entries] */
    uint32_t seam_closing;                    /* 1: also build symmetric matchers that re-match
                                                 the rows around the top/bottom wrap (default) [--no-seam-closing] */
} vqtex_model_params;

VQTEX_API void vqtex_model_params_init(vqtex_model_params* params);

typedef struct vqtex_synth_params {
    uint32_t struct_size;      /* set by vqtex_synth_params_init */
    vqtex_model_params model;
    vqtex_search search;       /* [--tsvq / --exhaustive] */
    uint32_t backtrack;        /* TSVQ leaves visited per search, L [--backtrack] */
    uint32_t width, height;    /* output size, 1 to 16384 each [--size] */
    uint64_t seed;             /* [--seed] */
    vqtex_init init;           /* [--init parent|noise] */
    uint32_t tolerance;        /* near-ties within best*(1+tolerance/256) are chosen among at
                                  random (seeded, per pixel); 0 = nearest only [--tolerance] */
    uint32_t threads;          /* 0 = all cores [--threads] */
    vqtex_progress_fn progress;
    void* progress_user;
} vqtex_synth_params;

VQTEX_API void vqtex_synth_params_init(vqtex_synth_params* params);

/* Figures from a synthesis, for benchmarks and tools. */
typedef struct vqtex_synth_stats {
    uint32_t levels;
    vqtex_shape shapes[VQTEX_MAX_LEVELS];
    uint32_t training_vectors[VQTEX_MAX_LEVELS]; /* example neighbourhoods per level */
    uint32_t codewords[VQTEX_MAX_LEVELS];        /* leaves per level (exhaustive: candidates) */
    uint32_t tree_depth[VQTEX_MAX_LEVELS];
    uint64_t model_bytes;                        /* memory held by codebooks or candidates */
    double analyse_seconds;
    double synthesise_seconds;
} vqtex_synth_stats;

/* Synthesise a new texture of params->width x params->height from an example
 * (paper sections 2-4). The output tiles seamlessly. `out` receives a new
 * image (free with vqtex_image_free); stats and error may be NULL. */
VQTEX_API vqtex_status vqtex_synthesize(const vqtex_synth_params* params, const vqtex_image* example,
                                        vqtex_image* out, vqtex_synth_stats* stats,
                                        vqtex_error* error);

#ifdef __cplusplus
}
#endif

#endif /* VQTEX_H */

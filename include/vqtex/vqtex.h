/* vqtex.h - the public C API of vqtex, a texture codec after Wei & Levoy,
 * "Fast Texture Synthesis using Tree-structured Vector Quantization"
 * (SIGGRAPH 2000).
 *
 * Conventions
 * - Every function returns a vqtex_status; VQTEX_OK is 0. When a vqtex_error
 *   pointer is given it receives the status and a one-line detail saying
 *   what went wrong, where, and what to do.
 * - Params structs are filled with defaults by their *_init function, then
 *   tweaked. The init function stamps the struct size (with
 *   VQTEX_LAYOUT_MARK on the structs whose fields this version rearranged),
 *   so a library can tell a caller built against another version of this
 *   header: such a struct is refused with VQTEX_ERROR_INVALID_ARGUMENT and a
 *   detail saying so.
 * - Images are 8-bit, 1 to 4 channels interleaved (grey, grey+alpha, RGB,
 *   RGBA), rows packed with no padding, at most VQTEX_MAX_SIDE on a side.
 *   Images the library returns are freed with vqtex_image_free().
 * - Calls on different data may run concurrently. The only process-wide
 *   state is set once and holds no data of any call: the SIMD kernels
 *   (chosen at first use from the CPU and VQTEX_SIMD) and the worker
 *   threads (see threads below).
 * - Determinism: output bytes depend only on the inputs, the parameters and
 *   the seed; never on the thread count, the CPU's SIMD level or the run.
 *
 * Libraries
 * - vqtex_decoder, the decoder library, provides: vqtex_version,
 *   vqtex_version_string, vqtex_status_message, vqtex_image_free,
 *   vqtex_free, vqtex_volume_free, vqtex_decode_params_init, vqtex_decode,
 *   vqtex_decode_mips, vqtex_inspect and vqtex_decode_volume.
 * - vqtex, the full library, holds the decoder's calls and every other:
 *   synthesis (vqtex_synthesize, vqtex_synthesize_volume), encoding
 *   (vqtex_encode, vqtex_encode_volume), filling (vqtex_fill, vqtex_extend)
 *   and their *_init and *_preset functions.
 *
 * Changes in this version of the header
 * - vqtex_synth_params: the fields both engines read are at the top level
 *   (width, height, seed, levels, example_tileable, threads, progress); the
 *   coherent engine's are in .coherent, the paper engine's in .paper
 *   (shapes, tsvq, search, backtrack, init, tolerance).
 * - The model params are split: levels and example_tileable are common
 *   fields of the params that use them, the 2D shapes are .paper.shapes or
 *   .trees.shapes, and the codebook fields are vqtex_tsvq_params
 *   (vqtex_tsvq_params_init).
 * - vqtex_encode_params: quality is an input only (the preset no longer
 *   writes it); the fields only a trees file uses are in .trees, which
 *   vqtex_encode_params_preset fills. vqtex_encode_stats.quality says what
 *   the file was made at, for trees files and atlas files alike.
 *   vqtex_volume_encode_params_preset fills an animation's the same way.
 * - vqtex_volume_encode_params holds its own fields instead of a nested
 *   vqtex_encode_params: its codebook kind (a space-time atlas by default,
 *   format version 22), quality and target size, then the trees' fields.
 *   vqtex_encode_stats reports an animation's atlas (atlas_frames,
 *   atlas_first_frame), vqtex_file_info its frame count (atlas_frames).
 * - VQTEX_MAX_SIDE: the largest example side (and example frame count).
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

/* Added to the struct_size that vqtex_synth_params_init,
   vqtex_encode_params_init and vqtex_volume_encode_params_init stamp: their
   fields were rearranged in this version, and the earlier layouts of the
   first two had the same size, so the size alone could not refuse a caller
   built against the earlier header. */
#define VQTEX_LAYOUT_MARK (2u << 24)

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
    VQTEX_ERROR_BAD_MAGIC = 6,        /* not a vqtex file */
    VQTEX_ERROR_UNSUPPORTED_VERSION = 7, /* a format version this library cannot read */
    VQTEX_ERROR_TRUNCATED = 8,        /* the file ends early */
    VQTEX_ERROR_CHECKSUM = 9,         /* the file's checksum does not match its bytes */
    VQTEX_ERROR_CORRUPT = 10,         /* inconsistent or invalid data inside the file */
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

/* The same with 16-bit samples (0 to 65535, interleaved): a map of a
 * material set that keeps more than 8 bits (vqtex_map, vqtex_map_image). */
typedef struct vqtex_image16 {
    uint32_t width;
    uint32_t height;
    uint32_t channels; /* 1 to 4 */
    uint16_t* pixels;  /* width * height * channels samples */
} vqtex_image16;

/* Frees pixels the library allocated and zeroes the struct; NULL is fine. */
VQTEX_API void vqtex_image_free(vqtex_image* image);
VQTEX_API void vqtex_image16_free(vqtex_image16* image);

/* The largest side of an example, and the most frames of an example
 * sequence: positions in the example are stored as 16-bit coordinates. An
 * example image also has at most 2^30 pixels. */
#define VQTEX_MAX_SIDE 65536

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

/* How the paper's TSVQ codebooks are trained from an example's
 * neighbourhoods (paper section 4), for the paper's engine, trees files and
 * animations. Zero in any field means "the default". CLI flags in brackets. */
typedef struct vqtex_tsvq_params {
    uint32_t codewords[VQTEX_MAX_LEVELS];     /* leaves per level, [0] finest; 0 = codeword_fraction [--codewords] */
    float codeword_fraction;                  /* leaves as a fraction of the training vectors [--codewords] */
    float train_fraction;                     /* train on this fraction of the vectors (1 = all) [--train-fraction] */
    uint32_t train_count;                     /* or at most this many per level (0 = no cap) */
    vqtex_leaf leaf;                          /* [--leaf] */
    float distortion_threshold;               /* stop splitting at this mean SSD per vector (0 = off) */
    uint64_t training_seed;                   /* seeds the training subset */
    uint32_t entries_per_leaf;                /* outputs per TSVQ leaf, 1 to 64 (0 = default) [--entries] */
    uint32_t no_entry_keys;                   /* 1: entries carry no key and are chosen at random
                                                 (smaller file); 0: chosen by their adjacent pixels */
    uint32_t closing_divisor;                 /* seam-closing trees get 1/this of the leaves (0 = 1) */
    uint32_t closing_window;                  /* seam-closing window size, odd (0 = the causal window's) */
    uint32_t seam_closing;                    /* 1: also build symmetric matchers that re-match
                                                 the rows around the top/bottom wrap (default) [--no-seam-closing] */
} vqtex_tsvq_params;

/* Defaults: every example neighbourhood a leaf, all of them trained on,
 * medoid leaves, seam closing on. */
VQTEX_API void vqtex_tsvq_params_init(vqtex_tsvq_params* params);

typedef enum vqtex_engine {
    /* Synthesis of example coordinates, coarse to fine, each pixel choosing
     * among the k-coherence candidates of its neighbours by appearance-space
     * neighbourhoods (Lefebvre & Hoppe 2005, 2006; Tong et al. 2002): keeps
     * the example's structure (default). Reads the common fields and
     * `coherent`. */
    VQTEX_ENGINE_COHERENT = 0,
    /* Wei & Levoy's per-pixel search over causal neighbourhoods (paper
     * sections 2-4). Reads the common fields and `paper`. With
     * paper.init = VQTEX_INIT_NOISE and paper.tsvq.seam_closing = 0 it is
     * the paper's algorithm exactly [--paper]. */
    VQTEX_ENGINE_PAPER = 1
} vqtex_engine;

/* The coherent engine's own parameters. */
typedef struct vqtex_coherent_params {
    uint32_t coherence;        /* candidates per neighbour: its shifted source and the example
                                  positions that look most like it, 1 to 16 [--coherence] */
    uint32_t passes;           /* correction passes per level (the finest: one fewer, then a colour pass), 1 to 8 [--passes] */
    uint32_t jitter;           /* variety: seeded displacement of each level's coordinates, in
                                  1/256 of the level's spacing, 0 to 1024 [--jitter] */
    uint32_t blend;            /* radius of the blend of the copies that meet at the output's seams
                                  (an animation's: in each frame), 0 (none) to 3; default 2 [--blend] */
    uint32_t relocate;         /* still textures: positions tried per copy by the copy relocation,
                                  which moves whole copies to where they fit the copies around
                                  them; 0 (none) to 1024, default 64 [--relocate] */
    uint32_t edge_guard;       /* still textures: a copy cut off by the example's edge ends in a seam:
                                  no position within this many example pixels of where it would go
                                  on is taken beside it; 0 (none) to 64, default 8 [--edge-guard] */
    uint32_t cut;              /* how far, in output pixels, a straight border between two copies
                                  may move to where they agree (minimum-error cuts; an animation's:
                                  in each frame); 0 (none) to 16, default 8 [--cut] */
    uint32_t margin;           /* still textures: copies are laid out inside the example less a frame
                                  of this many pixels, which the cuts then use (fewer straight seams;
                                  the frame's own values are rarer); 0 (none) to 16, default 0
                                  [--margin]. Not stored in files. */
    uint32_t cover;            /* still textures: how far, in output pixels, a third copy laid over
                                  a long border between two copies may reach into each, cut in
                                  along where it agrees with them (fewer straight seams);
                                  0 (none) to 16, default 8 [--cover] */
    uint32_t quilt;            /* still textures: 1 lays the output out by image quilting with the
                                  patch insertion cut (blocks of half the example's shorter side, at
                                  most 64; the layout of format 21) instead of the engine's passes,
                                  cuts and covers; needs an example of at least 16x16; default 0
                                  [--quilt] */
} vqtex_coherent_params;

/* The paper's engine's own parameters. */
typedef struct vqtex_paper_params {
    vqtex_shape shapes[VQTEX_MAX_LEVELS]; /* [0] = finest; {0,0,0} = default [--shapes] */
    vqtex_tsvq_params tsvq;    /* how the matchers are built (the codeword and training
                                  fields: search = VQTEX_SEARCH_TSVQ only) */
    vqtex_search search;       /* [--tsvq / --exhaustive] */
    uint32_t backtrack;        /* TSVQ leaves visited per search, L [--backtrack] */
    vqtex_init init;           /* [--init parent|noise] */
    uint32_t tolerance;        /* near-ties within best*(1+tolerance/256) are chosen among at
                                  random (seeded, per pixel); 0 = nearest only [--tolerance] */
} vqtex_paper_params;

typedef struct vqtex_synth_params {
    uint32_t struct_size;      /* set by vqtex_synth_params_init */
    vqtex_engine engine;       /* [--paper] */
    /* Common to both engines. */
    uint32_t width, height;    /* output size, 1 to 16384 each [--size] */
    uint64_t seed;             /* [--seed] */
    uint32_t levels;           /* pyramid depth, 1 to VQTEX_MAX_LEVELS; 0 = automatic [--levels] */
    uint32_t example_tileable; /* 1: the example wraps (toroidal neighbourhoods) [--tileable-example] */
    uint32_t threads;          /* 0 = all cores [--threads]. Worker threads are kept for the
                                  process's life, idle between calls, and shared by every
                                  call; a call that finds them busy starts its own. */
    vqtex_progress_fn progress;
    void* progress_user;
    /* Each engine's own; the other engine's are not read. */
    vqtex_coherent_params coherent;
    vqtex_paper_params paper;
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

/* ---- The codec -------------------------------------------------------------
 * The encoder builds the model of an example and writes only its codebooks
 * into a compact file; the decoder regenerates a texture of any size from
 * the file by synthesis. See docs/FORMAT.md. */

#define VQTEX_QUALITY_DEFAULT 50

typedef enum vqtex_codebook {
    /* TSVQ codebooks (paper section 6), decoded by the paper's engine: the
     * paper's literal codec, for comparison [--trees]. Uses the common
     * fields and `trees`. Animations (vqtex_encode_volume) always store
     * trees. */
    VQTEX_CODEBOOK_TREES = 0,
    /* An atlas: the example (or a crop of it) as an AV1 image, decoded by
     * the coherent engine, which keeps the example's structure (default for
     * still textures). Uses the common fields only [--atlas]. */
    VQTEX_CODEBOOK_ATLAS = 1
} vqtex_codebook;

/* What a trees file is made of: its neighbourhoods, codebooks and the
 * precision they are stored at. vqtex_encode_params_preset fills it. */
typedef struct vqtex_trees_params {
    vqtex_shape shapes[VQTEX_MAX_LEVELS]; /* [0] = finest; {0,0,0} = default [--shapes] */
    vqtex_tsvq_params tsvq;     /* [--codewords, --entries, --no-entry-keys, --closing-*] */
    uint32_t precision;         /* bits per codeword and key sample, 1 to 8 [--precision] */
    uint32_t pixel_precision;   /* bits per output pixel sample, 1 to 8 [--pixel-precision] */
    uint32_t smoothing;         /* 1 = exact codewords; 2..8 = taps away from the pixel averaged in
                                   blocks of that size (smaller file, coarser matching) [--smoothing] */
    uint32_t backtrack;         /* TSVQ leaves the decoder visits per search, 1 to 255 [--backtrack] */
    vqtex_init init;            /* how decoding starts each level */
} vqtex_trees_params;

/* Whether an example wraps (vqtex_encode_params.example_tileable). DETECT:
 * an atlas file of a still image or a map set wraps when the example (every
 * map) tiles seamlessly and does not repeat a tile of a quarter of its side
 * or less, and the atlas is the whole example; unless the example repeats a
 * tile, it is decoded with the period bar, so that the output does not
 * repeat the example on a grid (docs/ATLAS.md "Examples that tile"). Trees
 * files and animations do not wrap. YES: the example wraps, as trees,
 * animations and atlases. NO: it does not. */
#define VQTEX_TILEABLE_DETECT 0u
#define VQTEX_TILEABLE_YES 1u
#define VQTEX_TILEABLE_NO 2u

/* How the output of a wrapping atlas is laid out (vqtex_encode_params.layout).
 * AUTO: the encoder decodes the file both ways and keeps quilting (format 21)
 * where it keeps the example's structure better, the coherent engine
 * elsewhere (docs/ATLAS.md "Examples that tile"). COHERENT: always the
 * engine. QUILT: quilting wherever the atlas wraps and is the whole example.
 * An atlas that does not wrap is always laid out by the engine. */
#define VQTEX_LAYOUT_AUTO 0u
#define VQTEX_LAYOUT_COHERENT 1u
#define VQTEX_LAYOUT_QUILT 2u

typedef struct vqtex_encode_params {
    uint32_t struct_size;       /* set by vqtex_encode_params_init */
    vqtex_codebook codebook;    /* what the file stores: an atlas (default) or TSVQ trees [--trees] */
    /* Common to both codebooks. */
    uint32_t quality;           /* 0 (smallest file) to 100 (best texture), default
                                   VQTEX_QUALITY_DEFAULT [--quality]. An atlas: its byte budget, 4 KB
                                   per 128x128 pixels at 50, doubling every 25 points. Trees: reported
                                   in the stats only; `trees` holds what the preset made of it */
    uint64_t target_size;       /* bytes; nonzero: instead of quality, the best atlas or trees preset
                                   whose file fits [--target-size] */
    uint32_t levels;            /* pyramid depth, 1 to VQTEX_MAX_LEVELS; 0 = automatic [--levels] */
    uint32_t example_tileable;  /* VQTEX_TILEABLE_DETECT (0, default), _YES or _NO: whether the
                                   example wraps [--tileable-example, --no-tileable-example] */
    uint64_t seed;              /* default decoding seed stored in the file [--seed] */
    uint32_t threads;           /* 0 = all cores [--threads] */
    vqtex_progress_fn progress;
    void* progress_user;
    /* Atlas of one image only: VQTEX_LAYOUT_AUTO (0, default), _COHERENT or
       _QUILT [--layout auto|coherent|quilt] */
    uint32_t layout;
    /* Trees only. */
    vqtex_trees_params trees;
} vqtex_encode_params;

/* Defaults: an atlas at VQTEX_QUALITY_DEFAULT, `trees` from that preset. */
VQTEX_API void vqtex_encode_params_init(vqtex_encode_params* params);
/* Fills params->trees from a quality preset, 0 (smallest file) to 100 (best
 * texture) [--quality]. Every other field, quality included, is untouched:
 * set quality to the same value for the stats to report it. */
VQTEX_API vqtex_status vqtex_encode_params_preset(vqtex_encode_params* params, int quality);

typedef struct vqtex_encode_stats {
    uint64_t bytes;
    uint32_t quality;        /* the quality the file was made at: params->quality, or with
                                target_size the trees preset the search chose, or 0 for an atlas
                                chosen for a target size (its bytes, not a quality, decided it);
                                0 for an animation */
    uint32_t levels;
    uint32_t codewords[VQTEX_MAX_LEVELS];
    uint32_t entries[VQTEX_MAX_LEVELS];
    double seconds;
    uint32_t attempts;       /* encodes tried by the target-size search */
    /* An atlas file's atlas: its size and where it lies in the example;
     * atlas_kind 0 = the whole example, 1 = a part of it (a crop), 2 = the
     * tile a repeating example is made of (docs/ATLAS.md "Large examples").
     * All 0 for trees files. */
    uint32_t atlas_width, atlas_height, atlas_x, atlas_y;
    uint32_t atlas_kind;
    /* An animation's atlas: its frames and the example frame it starts at
     * (0 for a still texture). */
    uint32_t atlas_frames, atlas_first_frame;
    /* 1: the atlas wraps (the example tiles and the atlas is all of it). */
    uint32_t atlas_wraps;
    /* 1: the example's wrap is seamless (every map's, for a set), whether
     * or not the atlas wraps (docs/ATLAS.md "Examples that tile"). */
    uint32_t example_tiles;
    /* 1: the atlas wraps and is decoded with the period bar (format 15 or
     * 16): no copy shows the example again a period further on. */
    uint32_t period_bar;
    /* 1: the output is laid out by quilting (formats 19 to 21). */
    uint32_t quilt;
} vqtex_encode_stats;

/* Encodes an example into a new buffer (*data, *size), freed with
 * vqtex_free(). On failure *data is NULL. stats and error may be NULL. */
VQTEX_API vqtex_status vqtex_encode(const vqtex_encode_params* params, const vqtex_image* example,
                                    uint8_t** data, size_t* size, vqtex_encode_stats* stats,
                                    vqtex_error* error);

VQTEX_API void vqtex_free(void* data);

/* ---- Material sets ---------------------------------------------------------
 * Several maps of one surface (albedo, normals, gloss, height...) in one
 * file, synthesised once: every map is read through the same coordinates,
 * so the decoded maps are aligned pixel for pixel. The synthesis matches a
 * guide made from all the maps (docs/FORMAT.md §4.15). A set of one normal
 * or data map is how such a map is stored alone. Atlas files only. */

typedef enum vqtex_map_kind {
    VQTEX_MAP_COLOUR = 0, /* colour; a 2- or 4-channel map's last channel is straight alpha */
    VQTEX_MAP_NORMAL = 1, /* tangent-space normals, 3 channels, each component mapped from [-1, 1]
                             to 0..255; decoded normals have unit length */
    VQTEX_MAP_DATA = 2    /* values as they are: gloss, roughness, height, masks */
} vqtex_map_kind;

#define VQTEX_MAX_MAPS 16
#define VQTEX_MAX_MAP_NAME 32 /* characters of [A-Za-z0-9_.-] */

typedef struct vqtex_map {
    const char* name;     /* 1 to VQTEX_MAX_MAP_NAME characters of [A-Za-z0-9_.-], distinct in a set */
    vqtex_map_kind kind;
    uint32_t weight;      /* 0..8: how much the map counts in the guide; 0 = the kind's default
                             (colour 2, height-like data named height/disp/bump 2, others 1) */
    vqtex_image image;    /* every map of a set has the same size; 1 to 4 channels (normal: 3) */
    const vqtex_image16* image16; /* or, when not NULL, the map's 16-bit samples (`image` is then
                                     not read): the file keeps 12 bits of them */
} vqtex_map;

/* Encodes a set of 1 to VQTEX_MAX_MAPS maps into one file (an atlas: the
 * `codebook` field must be VQTEX_CODEBOOK_ATLAS). `quality` gives each map
 * a single image's budget, `target_size` is shared: the maps are coded at
 * one AV1 level, each made finer by how much less contrast it has than the
 * set's most contrasty map, so each takes the bytes its content needs. */
VQTEX_API vqtex_status vqtex_encode_maps(const vqtex_encode_params* params, const vqtex_map* maps, uint32_t count,
                                         uint8_t** data, size_t* size, vqtex_encode_stats* stats,
                                         vqtex_error* error);

typedef struct vqtex_map_image {
    char name[VQTEX_MAX_MAP_NAME + 1];
    vqtex_map_kind kind;
    uint32_t bits;          /* bits a sample in the file: 8, or 12 for a map made from 16-bit samples */
    vqtex_image image;      /* bits 8 (free with vqtex_image_free) */
    vqtex_image16 image16;  /* bits 12: widened to 16 bits (free with vqtex_image16_free) */
} vqtex_map_image;

#define VQTEX_SEED_FROM_FILE UINT64_MAX

typedef struct vqtex_decode_params {
    uint32_t struct_size;    /* set by vqtex_decode_params_init */
    uint32_t width, height;  /* output size, 1 to 16384 each; 0 = the exemplar's size [--size] */
    uint64_t seed;           /* VQTEX_SEED_FROM_FILE (default) or any seed [--seed] */
    uint32_t threads;        /* 0 = all cores; the output is the same for any count [--threads] */
    uint64_t memory_limit;   /* bytes the decoder may allocate; default 1 GiB [--memory-limit] */
    vqtex_progress_fn progress;
    void* progress_user;
} vqtex_decode_params;

VQTEX_API void vqtex_decode_params_init(vqtex_decode_params* params);

/* Decodes a file into a new image (free with vqtex_image_free). */
VQTEX_API vqtex_status vqtex_decode(const vqtex_decode_params* params, const uint8_t* data, size_t size,
                                    vqtex_image* out, vqtex_error* error);

/* Decodes every map of a file, in the file's order, through one synthesis.
 * A file that is not a set (a single colour image, any format) gives one
 * colour map named "texture". `maps` must hold `capacity` entries
 * (VQTEX_MAX_MAPS is always enough); *count receives how many were
 * written. vqtex_decode on a set gives its first map (when it has 8 bits). */
VQTEX_API vqtex_status vqtex_decode_maps(const vqtex_decode_params* params, const uint8_t* data, size_t size,
                                         vqtex_map_image* maps, uint32_t capacity, uint32_t* count,
                                         vqtex_error* error);

/* The coordinates a decode of a still atlas file (format 3 to 11, 13, 14)
 * reads its texture from: a 2-channel image of the output's size holding,
 * for every output pixel, the (x, y) of the exemplar pixel that its copy
 * puts there. The atlas is the exemplar or a part of it; the file says
 * where the part lies (format 13 and 14; vqtex_file_info's atlas_x,
 * atlas_y), so the coordinates are the exemplar's own pixels. (A file of
 * format 10 or 11 whose part was not the exemplar's top-left corner, as
 * encoders before format 13 wrote for large examples, gives the part's
 * pixels.) The decoder blends neighbouring copies over a few pixels at
 * seams; the coordinates are each pixel's own copy. For applying one
 * layout to maps of your own (free with vqtex_image16_free). */
VQTEX_API vqtex_status vqtex_decode_coords(const vqtex_decode_params* params, const uint8_t* data, size_t size,
                                           vqtex_image16* coords, vqtex_error* error);

/* Decodes the whole synthesised pyramid as a mip chain: levels[0] is the
 * texture, each next level half the size (rounded up) down to 1x1. For a
 * trees file the synthesised pyramid levels come first; for an atlas file
 * only levels[0] is synthesised. Below those, levels are
 * the binomial-filtered, toroidal reduction of the one above. `levels` must hold
 * `capacity` images; *count receives how many were written. */
VQTEX_API vqtex_status vqtex_decode_mips(const vqtex_decode_params* params, const uint8_t* data,
                                         size_t size, vqtex_image* levels, uint32_t capacity,
                                         uint32_t* count, vqtex_error* error);

#define VQTEX_MAX_SECTIONS 64

typedef struct vqtex_section_info {
    char tag[5];             /* "LEVL", "HIST", "TOPO", "CODE", "ENTR" */
    uint32_t level;
    uint32_t kind;           /* 0 causal tree (or none), 1 closing tree */
    uint64_t raw_bytes;
    uint64_t stored_bytes;   /* in the file, including the 16-byte section header */
} vqtex_section_info;
/* An atlas file in the compact layout (every atlas file this library
 * writes) has no sections: vqtex_inspect
 * lists its two parts as "ATLS" (the AV1 bitstream) and "SYNP" (the stored
 * synthesis parameters, 0 bytes when they are the defaults), with
 * raw_bytes = stored_bytes = their bytes in the file and no section header;
 * the rest of file_bytes is the header and the checksum. */

typedef struct vqtex_file_info {
    uint32_t format_version;
    uint64_t file_bytes;
    uint32_t exemplar_width, exemplar_height, channels, levels;
    uint32_t seam_closing, init, backtrack, precision, pixel_precision;
    uint64_t seed;
    vqtex_shape shapes[VQTEX_MAX_LEVELS];
    uint32_t codewords[VQTEX_MAX_LEVELS];          /* causal tree leaves */
    uint32_t entries[VQTEX_MAX_LEVELS];            /* causal tree entries */
    uint32_t closing_codewords[VQTEX_MAX_LEVELS];
    uint32_t section_count;
    vqtex_section_info sections[VQTEX_MAX_SECTIONS];
    uint32_t exemplar_frames;                      /* animated texture: frames of the example (an atlas
                                                      animation: of its atlas, the default output count);
                                                      0 for a still one */
    uint8_t window_frames[VQTEX_MAX_LEVELS];       /* animated texture: D of each level's {RxCxD,k} */
    uint32_t atlas_width, atlas_height;            /* atlas texture: the atlas's size; 0 otherwise */
    uint32_t blend;                                /* atlas texture or animation: radius of the blend at seams
                                                      the decoder uses (0: none); 0 otherwise */
    uint32_t relocate;                             /* atlas texture: positions tried per copy by the copy
                                                      relocation the decoder uses (0: none); 0 otherwise */
    uint32_t edge_guard;                           /* atlas texture: the edge guard the decoder uses, in atlas
                                                      pixels (0: none); 0 otherwise */
    uint32_t cut;                                  /* atlas texture or animation: the reach of the cuts
                                                      between copies the decoder uses, in output pixels (0:
                                                      none); 0 otherwise */
    uint32_t cover;                                /* atlas texture: the reach of the covers over long borders
                                                      the decoder uses, in output pixels (0: none); 0 otherwise */
    uint32_t atlas_wraps;                          /* atlas texture: 1 when the atlas wraps (a tileable example,
                                                      or the tile a repeating example is made of) */
    uint32_t period_bar;                           /* atlas texture: 1 when a wrapping atlas is decoded with the
                                                      period bar (formats 15 and 16) */
    uint32_t quilt_block;                          /* atlas texture: the side of the blocks the output is
                                                      laid out with by quilting (formats 19 to 21); 0 otherwise */
    uint32_t atlas_frames;                         /* atlas animation (formats 12, 22): the atlas's frames, the
                                                      default output frame count; 0 otherwise */
    uint32_t map_count;                            /* maps in the file: 1 but for a material set */
    struct {
        char name[VQTEX_MAX_MAP_NAME + 1];         /* "texture" for a file that is not a set */
        vqtex_map_kind kind;
        uint32_t channels;
        uint32_t bits;                             /* bits a sample in the file: 8, or 12 for a 16-bit map */
        uint64_t bytes;                            /* its coded atlas */
    } maps[VQTEX_MAX_MAPS];
    uint32_t atlas_x, atlas_y;                     /* atlas texture: where the atlas lies in the exemplar (its
                                                      top-left corner; 0, 0 when it is the whole exemplar or
                                                      its top-left corner, and in files before format 13) */
    int32_t map_predicted_from[VQTEX_MAX_MAPS];    /* material set (formats 17 and 18): the index of the map
                                                      that map i is coded as a prediction from, its atlas
                                                      holding only what that map does not predict; -1 when
                                                      map i is coded as it is */
} vqtex_file_info;

/* Verifies and describes a file (everything the decoder checks). */
VQTEX_API vqtex_status vqtex_inspect(const uint8_t* data, size_t size, uint64_t memory_limit,
                                     vqtex_file_info* info, vqtex_error* error);

/* ---- Constrained synthesis: hole filling and extrapolation -----------------
 * Pixels under a mask are synthesised so that they look like the rest of the
 * image and meet it without a visible boundary (paper section 5.1); every
 * other pixel is returned byte for byte. The example is the image itself
 * outside the mask, or a separate example image. The image is not treated
 * as periodic: reads past its border are mirrored. */

typedef enum vqtex_fill_method {
    /* Spiral order from the hole's border inwards, two passes per pyramid
     * level with symmetric neighbourhoods (paper section 5.1, default). */
    VQTEX_FILL_TWO_PASS = 0,
    /* One raster-order pass per level with causal neighbourhoods: the
     * paper's Fig. 12c, seams at the right and bottom edges. For comparison. */
    VQTEX_FILL_CAUSAL = 1
} vqtex_fill_method;

typedef struct vqtex_fill_params {
    uint32_t struct_size;       /* set by vqtex_fill_params_init */
    uint32_t levels;            /* pyramid depth; 0 = the deepest the image and mask allow [--levels] */
    vqtex_search search;        /* [--exhaustive] */
    uint32_t backtrack;         /* TSVQ leaves visited per search [--backtrack] */
    float codeword_fraction;    /* TSVQ leaves per example neighbourhood, (0, 1] [--codewords] */
    uint32_t tolerance;         /* near-ties within best*(1+tolerance/256) are chosen among with
                                   the seed; 0 = nearest only [--tolerance] */
    uint64_t seed;              /* [--seed] */
    vqtex_fill_method method;   /* [--method two-pass|causal] */
    uint32_t threads;           /* 0 = all cores; the output is the same for any count [--threads] */
    vqtex_progress_fn progress; /* stages ANALYSE (trees built) and SYNTHESISE (pixels) */
    void* progress_user;
} vqtex_fill_params;

VQTEX_API void vqtex_fill_params_init(vqtex_fill_params* params);

typedef struct vqtex_fill_stats {
    uint32_t levels;
    vqtex_shape shapes[VQTEX_MAX_LEVELS];       /* [0] = finest; symmetric for the two-pass method */
    uint32_t examples[VQTEX_MAX_LEVELS];        /* usable example neighbourhoods per level */
    uint32_t block_examples[VQTEX_MAX_LEVELS];  /* pass-1 example blocks per level (0: coarsest) */
    uint32_t filled[VQTEX_MAX_LEVELS];          /* pixels synthesised per level */
    double analyse_seconds;
    double fill_seconds;
} vqtex_fill_stats;

/* Fills the pixels of `image` where `mask` (1 channel, image's size) is
 * non-zero. `example` may be NULL (the image outside the mask is the
 * example) or an image with image's channel count. `out` receives a new
 * image of image's size (free with vqtex_image_free); stats and error may be
 * NULL. A mask that leaves too little example fails with
 * VQTEX_ERROR_IMAGE_TOO_SMALL. */
VQTEX_API vqtex_status vqtex_fill(const vqtex_fill_params* params, const vqtex_image* image,
                                  const vqtex_image* mask, const vqtex_image* example,
                                  vqtex_image* out, vqtex_fill_stats* stats, vqtex_error* error);

/* Extrapolation: places `image` at (x, y) in a new width x height canvas
 * (1 to 16384 per side, the image wholly inside) and synthesises the rest
 * of the canvas, plus the pixels of `image` where `mask` is non-zero (mask
 * may be NULL; otherwise 1 channel, image's size). */
VQTEX_API vqtex_status vqtex_extend(const vqtex_fill_params* params, const vqtex_image* image,
                                    const vqtex_image* mask, uint32_t width, uint32_t height,
                                    uint32_t x, uint32_t y, const vqtex_image* example,
                                    vqtex_image* out, vqtex_fill_stats* stats, vqtex_error* error);

/* ---- Animated textures (paper section 5.2) ----------------------------------
 * Motion textures (fire, smoke, water, flicker) as volumes in (x, y, t): 3D
 * pyramids and neighbourhoods {RxCxD,k}, synthesised frame after frame,
 * coarse to fine. The output tiles in space and loops in time. A file holds
 * either a still texture or an animation: vqtex_decode on an animation (and
 * vqtex_decode_volume on a still texture) fails with INVALID_ARGUMENT. */

typedef struct vqtex_volume {
    uint32_t width;
    uint32_t height;
    uint32_t frames;
    uint32_t channels; /* 1 to 4 */
    uint8_t* pixels;   /* frame after frame, each width * height * channels bytes */
} vqtex_volume;

/* Frees pixels the library allocated and zeroes the struct; NULL is fine. */
VQTEX_API void vqtex_volume_free(vqtex_volume* volume);

/* A spatio-temporal neighbourhood {RxCxD,k}: the D/2 previous frames' full
 * RxC windows, the causal part of the current frame's RxC window, and full
 * windows about half as large on every axis at the k-1 coarser levels.
 * rows, cols and frames are odd. */
typedef struct vqtex_shape3 {
    uint8_t rows;
    uint8_t cols;
    uint8_t frames;
    uint8_t levels;
} vqtex_shape3;

typedef struct vqtex_volume_encode_params {
    uint32_t struct_size;          /* set by vqtex_volume_encode_params_init */
    /* What the file stores: a space-time atlas (default: a loop of frames
     * of the example, or of a part of it, as an AV1 sequence, decoded by
     * the coherent engine, format version 22) or the paper's TSVQ trees
     * (format version 2) [--trees]. */
    vqtex_codebook codebook;
    uint32_t quality;              /* 0 to 100, default VQTEX_QUALITY_DEFAULT [--quality]. An atlas:
                                      its byte budget (docs/ANIMATION.md); trees: the fields below */
    uint64_t target_size;          /* bytes; nonzero: an atlas, the best that fits [--target-size] */
    uint32_t levels;               /* pyramid depth, 1 to VQTEX_MAX_LEVELS; 0 = automatic [--levels] */
    uint32_t example_tileable;     /* 1: the example wraps in space [--tileable-example] */
    uint64_t seed;                 /* default decoding seed stored in the file [--seed] */
    uint32_t threads;              /* 0 = all cores [--threads] */
    vqtex_progress_fn progress;
    void* progress_user;
    vqtex_shape3 shapes[VQTEX_MAX_LEVELS]; /* [0] = finest; {0,0,0,0} = default [--shapes] */
    /* Trees only: the codebooks and their precision, as a still texture's
     * trees; its shapes are the 3D ones above. tsvq.seam_closing also
     * builds the loop-closing trees. */
    vqtex_tsvq_params tsvq;
    uint32_t precision;            /* bits per codeword and key sample, 1 to 8 [--precision] */
    uint32_t pixel_precision;      /* bits per output pixel sample, 1 to 8 [--pixel-precision] */
    uint32_t smoothing;            /* as vqtex_trees_params.smoothing [--smoothing] */
    uint32_t backtrack;            /* TSVQ leaves the decoder visits per search, 1 to 255 [--backtrack] */
    vqtex_init init;               /* how decoding starts each level */
} vqtex_volume_encode_params;

/* Defaults: a space-time atlas at VQTEX_QUALITY_DEFAULT. For trees: 3
 * levels (fewer for tiny examples), {5x5x5,2} and {5x5x5,1} at the coarsest
 * level, codebooks trained on a random 10% of the example's neighbourhoods
 * as the paper, loop closing on; the codebook sizes and precision of the
 * VQTEX_QUALITY_DEFAULT preset. */
VQTEX_API void vqtex_volume_encode_params_init(vqtex_volume_encode_params* params);
/* Fills the codebook sizes and precision from the quality preset of
 * vqtex_encode_params_preset, 0 to 100 [--quality]; the training fraction,
 * levels, shapes and every other field are untouched. */
VQTEX_API vqtex_status vqtex_volume_encode_params_preset(vqtex_volume_encode_params* params, int quality);

/* Encodes an example frame sequence (at least 1 frame; the paper uses 32).
 * An atlas (the default) is a segment of the example's loop, of the whole
 * example or a part of it, whichever scores best at the budget
 * (docs/ANIMATION.md). */
VQTEX_API vqtex_status vqtex_encode_volume(const vqtex_volume_encode_params* params, const vqtex_volume* example,
                                           uint8_t** data, size_t* size, vqtex_encode_stats* stats,
                                           vqtex_error* error);

/* Decodes an animation of `frames` frames (0 = the example's count, 1 to
 * 16384) of params->width x params->height (0 = the example's size). The
 * output loops: frame `frames` would be frame 0 again. */
VQTEX_API vqtex_status vqtex_decode_volume(const vqtex_decode_params* params, uint32_t frames, const uint8_t* data,
                                           size_t size, vqtex_volume* out, vqtex_error* error);

/* Synthesise an animation of `frames` frames (0 = the example's count, 1 to
 * 16384) of params->width x params->height from an example frame sequence,
 * without a file: the coherent engine, each output voxel a position (x, y, t)
 * in the example, frame after frame; every frame starts from the previous
 * one's positions one example frame later (the example is read as a loop
 * in time) and is corrected with neighbourhoods of the current and the
 * previous frame. The output tiles in space; its last frame is matched
 * against its first, so it loops in time (docs/ANIMATION.md says how well).
 * Uses params->engine (VQTEX_ENGINE_COHERENT only), the common fields,
 * coherent.passes, coherent.cut and coherent.blend (each frame's borders
 * between copies cut, then blended, where they meet); coherent.coherence
 * must be 1 and coherent.jitter 0; relocate, edge_guard and cover are not
 * used. The same bytes for any thread count; a version 22 file decodes as
 * this call on its atlas (a version 12 file as this call with cut 0).
 * `out` receives a new volume (free with vqtex_volume_free); stats and error
 * may be NULL. */
VQTEX_API vqtex_status vqtex_synthesize_volume(const vqtex_synth_params* params, const vqtex_volume* example,
                                               uint32_t frames, vqtex_volume* out, vqtex_synth_stats* stats,
                                               vqtex_error* error);

#ifdef __cplusplus
}
#endif

#endif /* VQTEX_H */

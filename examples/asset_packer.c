/* asset_packer.c - how an asset pipeline uses vqtex: encode a texture held
 * in memory into a compact .vqt blob, then decode a larger tileable texture
 * from the blob, all in memory, in plain C against the installed library.
 *
 *   cc asset_packer.c $(pkg-config --cflags --libs --static vqtex) -o asset_packer
 *   or: find_package(vqtex) and link vqtex::vqtex (see examples/CMakeLists.txt)
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <vqtex/vqtex.h>

/* A procedural 64x64 RGB example: soft diagonal stripes with a little
 * pseudo-random grain, so the example runs without any image files. */
static unsigned char* make_example(unsigned w, unsigned h) {
    unsigned char* px = malloc((size_t)w * h * 3);
    unsigned state = 12345u;
    if (!px) return NULL;
    for (unsigned y = 0; y < h; ++y)
        for (unsigned x = 0; x < w; ++x) {
            state = state * 1103515245u + 12345u;
            const unsigned grain = (state >> 16) % 24u;
            const unsigned band = ((x + y) % 16u) < 8u ? 60u : 180u;
            unsigned char* p = px + ((size_t)y * w + x) * 3;
            p[0] = (unsigned char)(band + grain);
            p[1] = (unsigned char)(band / 2u + grain);
            p[2] = (unsigned char)(40u + grain);
        }
    return px;
}

static int cancel_never(void* user, vqtex_stage stage, uint64_t done, uint64_t total) {
    (void)user; (void)stage; (void)done; (void)total;
    return 1;
}

int main(void) {
    const unsigned w = 64, h = 64;
    unsigned char* pixels = make_example(w, h);
    if (!pixels) return 1;
    printf("vqtex %s\n", vqtex_version_string());

    vqtex_encode_params ep;
    vqtex_encode_params_init(&ep);
    ep.quality = 20;
    vqtex_encode_params_preset(&ep, 20);
    ep.progress = cancel_never;
    vqtex_image example = {w, h, 3, pixels};
    uint8_t* blob = NULL;
    size_t blob_size = 0;
    vqtex_error err;
    if (vqtex_encode(&ep, &example, &blob, &blob_size, NULL, &err) != VQTEX_OK) {
        fprintf(stderr, "encode failed: %s (%s)\n", err.detail, vqtex_status_message(err.status));
        free(pixels);
        return 1;
    }
    printf("encoded %ux%u example into %zu bytes\n", w, h, blob_size);

    vqtex_decode_params dp;
    vqtex_decode_params_init(&dp);
    dp.width = 256;
    dp.height = 192;
    vqtex_image texture;
    if (vqtex_decode(&dp, blob, blob_size, &texture, &err) != VQTEX_OK) {
        fprintf(stderr, "decode failed: %s\n", err.detail);
        vqtex_free(blob);
        free(pixels);
        return 1;
    }
    /* The same blob, size and seed always give the same bytes. */
    vqtex_image again;
    int same = vqtex_decode(&dp, blob, blob_size, &again, &err) == VQTEX_OK &&
               memcmp(texture.pixels, again.pixels, (size_t)texture.width * texture.height * texture.channels) == 0;
    printf("decoded %ux%u tileable texture, deterministic: %s\n", texture.width, texture.height,
           same ? "yes" : "NO");

    /* A damaged blob is rejected with a specific error, never a crash. */
    blob[blob_size - 5] ^= 0xFF;
    vqtex_image bad;
    const vqtex_status st = vqtex_decode(&dp, blob, blob_size, &bad, &err);
    printf("damaged blob: %s\n", vqtex_status_message(st));

    vqtex_image_free(&texture);
    vqtex_image_free(&again);
    vqtex_free(blob);
    free(pixels);
    return (same && st != VQTEX_OK) ? 0 : 1;
}

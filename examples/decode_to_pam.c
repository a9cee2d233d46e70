/* decode_to_pam.c - the decoder on its own: read a .vqt file, synthesise a
 * still texture of any size from it and write it as a PAM image (netpbm's
 * format for 1 to 4 channels, readable by most image programs). Needs only
 * the decoder library, which has no training and no hole filling:
 *
 *   cc decode_to_pam.c $(pkg-config --cflags --libs --static vqtex) -o decode_to_pam
 *   or: find_package(vqtex) and link vqtex::vqtex_decoder (examples/CMakeLists.txt)
 *
 * Usage: decode_to_pam FILE.vqt OUT.pam [WIDTH HEIGHT]
 */
#include <stdio.h>
#include <stdlib.h>

#include <vqtex/vqtex.h>

static unsigned char* read_file(const char* path, size_t* size) {
    FILE* f = fopen(path, "rb");
    unsigned char* data = NULL;
    long n;
    if (!f) return NULL;
    if (fseek(f, 0, SEEK_END) == 0 && (n = ftell(f)) > 0 && fseek(f, 0, SEEK_SET) == 0) {
        data = malloc((size_t)n);
        if (data && fread(data, 1, (size_t)n, f) != (size_t)n) {
            free(data);
            data = NULL;
        }
        *size = (size_t)n;
    }
    fclose(f);
    return data;
}

static int write_pam(const char* path, const vqtex_image* img) {
    static const char* const tuple_types[] = {"GRAYSCALE", "GRAYSCALE_ALPHA", "RGB", "RGB_ALPHA"};
    const size_t bytes = (size_t)img->width * img->height * img->channels;
    FILE* f = fopen(path, "wb");
    int ok;
    if (!f) return 0;
    fprintf(f, "P7\nWIDTH %u\nHEIGHT %u\nDEPTH %u\nMAXVAL 255\nTUPLTYPE %s\nENDHDR\n", img->width, img->height,
            img->channels, tuple_types[img->channels - 1]);
    ok = fwrite(img->pixels, 1, bytes, f) == bytes;
    return fclose(f) == 0 && ok;
}

int main(int argc, char** argv) {
    vqtex_decode_params params;
    vqtex_image texture = {0};
    vqtex_error error;
    unsigned char* data;
    size_t size = 0;
    if (argc != 3 && argc != 5) {
        fprintf(stderr, "usage: %s FILE.vqt OUT.pam [WIDTH HEIGHT]\n", argv[0]);
        return 2;
    }
    data = read_file(argv[1], &size);
    if (!data) {
        fprintf(stderr, "cannot read %s\n", argv[1]);
        return 1;
    }
    vqtex_decode_params_init(&params);
    if (argc == 5) {
        params.width = (uint32_t)strtoul(argv[3], NULL, 10);
        params.height = (uint32_t)strtoul(argv[4], NULL, 10);
    }
    if (vqtex_decode(&params, data, size, &texture, &error) != VQTEX_OK) {
        fprintf(stderr, "%s: %s (%s)\n", argv[1], vqtex_status_message(error.status), error.detail);
        free(data);
        return 1;
    }
    free(data);
    if (!write_pam(argv[2], &texture)) {
        fprintf(stderr, "cannot write %s\n", argv[2]);
        vqtex_image_free(&texture);
        return 1;
    }
    printf("%s: %ux%u, %u channels\n", argv[2], texture.width, texture.height, texture.channels);
    vqtex_image_free(&texture);
    return 0;
}

#!/usr/bin/env python3
"""layers_check.py - the layers of codec/ as a dependency graph, checked.

Every #include "..." of every file under codec/ is an edge from the file's
folder to the included file's folder. The folders form one order

    common -> dsp -> engine -> tsvq -> format -> writer -> analysis -> fill -> api

and a file may include only its own folder and the folders before it (the
top-level CMakeLists.txt explains each layer). On top of the order, the two
libraries: the decode side (what vqtex_decoder compiles) must not include
the encode side, which is writer/, analysis/, fill/, the TSVQ training and
exhaustive search in tsvq/, and api/'s encode-side files (every api/ file
not named in API_DECODE_SIDE). The source lists of CMakeLists.txt must
agree: VQTEX_DECODER_SOURCES holds decode-side files only,
VQTEX_ENCODER_SOURCES encode-side files only, and every .cpp of codec/ is in
exactly one of them.

Besides codec/ files, a file may include the public header (vqtex/...) and,
on the encode side only, the metrics (metrics/). Anything else is an error.

Usage: layers_check.py SOURCE_DIR. Prints every violation as
FILE:LINE: reason, and exits 1 if there is any.
"""
import os
import re
import sys

LAYERS = ["common", "dsp", "engine", "tsvq", "format", "writer", "analysis", "fill", "api"]
# Folders whose files are all on the encode side.
ENCODE_FOLDERS = {"writer", "analysis", "fill"}
# Encode-side files inside folders that are otherwise the decoder's.
ENCODE_FILES = {
    "tsvq/tsvq_train.hpp", "tsvq/tsvq_train.cpp",
    "tsvq/search_exhaustive.hpp", "tsvq/search_exhaustive.cpp",
}
# api/ is split by file: these are the decoder library's C API; every other
# api/ file is built only into the full library, vqtex.
API_DECODE_SIDE = {
    "api/api.cpp", "api/decode_api.cpp", "api/api_support.hpp",
    "api/validate.hpp", "api/validate_decode.cpp",
    "api/coherent_options.hpp", "api/coherent_options.cpp",
}

INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"')


def is_encode_side(rel):
    folder = rel.split("/", 1)[0]
    if folder in ENCODE_FOLDERS or rel in ENCODE_FILES:
        return True
    return folder == "api" and rel not in API_DECODE_SIDE


def cmake_sources(src, name):
    text = open(os.path.join(src, "CMakeLists.txt"), encoding="utf-8").read()
    m = re.search(r"set\(" + name + r"\s+([^)]*)\)", text)
    if not m:
        return None
    return [s[len("codec/"):] for s in m.group(1).split() if s.startswith("codec/")]


def main():
    src = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..")
    codec = os.path.join(src, "codec")
    metrics = os.path.join(src, "metrics")
    errors = []
    files = []
    for folder in sorted(os.listdir(codec)):
        path = os.path.join(codec, folder)
        if not os.path.isdir(path):
            continue
        for name in sorted(os.listdir(path)):
            if name.endswith((".hpp", ".cpp", ".h")):
                files.append(folder + "/" + name)

    for rel in files:
        folder = rel.split("/", 1)[0]
        if folder not in LAYERS:
            errors.append(f"codec/{rel}:1: folder {folder}/ is in no layer (add it to the order)")
            continue
        with open(os.path.join(codec, rel), encoding="utf-8") as f:
            for number, line in enumerate(f, 1):
                m = INCLUDE.match(line)
                if not m:
                    continue
                target = m.group(1)
                where = f"codec/{rel}:{number}"
                if target.startswith("vqtex/"):
                    continue
                if os.path.isfile(os.path.join(codec, target)) and "/" in target:
                    included = target
                elif os.path.isfile(os.path.join(codec, folder, target)):
                    included = folder + "/" + target
                elif os.path.isfile(os.path.join(metrics, target)):
                    if not is_encode_side(rel):
                        errors.append(f'{where}: includes "{target}" (metrics/): the decode side measures nothing')
                    continue
                else:
                    errors.append(f'{where}: includes "{target}", which is neither in codec/ nor a public header')
                    continue
                to = included.split("/", 1)[0]
                if to not in LAYERS:
                    errors.append(f'{where}: includes "{target}" from folder {to}/, which is in no layer')
                    continue
                if LAYERS.index(to) > LAYERS.index(folder):
                    errors.append(f'{where}: includes "{target}": {folder}/ may not depend on {to}/, '
                                  f'which comes after it ({" -> ".join(LAYERS)})')
                elif not is_encode_side(rel) and is_encode_side(included):
                    errors.append(f'{where}: includes "{target}": a decode-side file may not include '
                                  f'the encode side')

    decoder = cmake_sources(src, "VQTEX_DECODER_SOURCES")
    encoder = cmake_sources(src, "VQTEX_ENCODER_SOURCES")
    if decoder is None or encoder is None:
        errors.append("CMakeLists.txt:1: no set(VQTEX_DECODER_SOURCES ...) and set(VQTEX_ENCODER_SOURCES ...)")
    else:
        for rel in decoder:
            if is_encode_side(rel):
                errors.append(f"CMakeLists.txt:1: VQTEX_DECODER_SOURCES lists codec/{rel}, an encode-side file")
        for rel in encoder:
            if not is_encode_side(rel):
                errors.append(f"CMakeLists.txt:1: VQTEX_ENCODER_SOURCES lists codec/{rel}, a decode-side file "
                              f"(the encoder library has the decoder's objects already)")
        listed = decoder + encoder
        for rel in files:
            if rel.endswith(".cpp") and listed.count(rel) != 1:
                errors.append(f"CMakeLists.txt:1: codec/{rel} is listed {listed.count(rel)} times "
                              f"in the libraries' sources (once expected)")

    for e in errors:
        print(e)
    if errors:
        print(f"layers check: {len(errors)} violation(s)", file=sys.stderr)
        return 1
    print(f"layers check: {len(files)} files of codec/ follow {' -> '.join(LAYERS)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env bash
# Regenerates bench/baseline_corpus.csv: vqtex at the default quality on the
# project's own corpus (no peers, no times), so that any change in file
# sizes or decoded quality shows up as a reviewed diff.
#   bench/baseline.sh [BUILD_DIR]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${1:-$root/build}"
"$build/vqtex-bench" "$root/corpus" --no-peers --no-times -q 50 --csv "$root/bench/baseline_corpus.csv" >/dev/null
echo "wrote bench/baseline_corpus.csv"

// test_coherent.cpp - the coherent engine (codec/engine/coherent_synthesis,
// appearance, coherence_sets): its pieces against slow reference
// implementations, determinism, and structure reproduced on a texture whose
// structure the test can measure.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>

#include "common/rng.hpp"
#include "engine/appearance.hpp"
#include "engine/coherence_sets.hpp"
#include "engine/coherent_synthesis.hpp"
#include "engine/copy_relocation.hpp"
#include "engine/pyramid.hpp"
#include "engine/seam_blend.hpp"
#include "test_support.hpp"

using namespace vqtex;

namespace {

// Rows of bricks: dark mortar lines 2 px wide, brick heights 10 px, brick
// lengths drawn from 14 to 26 px, each course starting at a random offset,
// brick shades varying. Its structure is measurable: the runs of brick
// pixels between mortar along rows and columns.
Image brick_wall(int w, int h, uint64_t seed) {
    Image img(w, h, 3);
    Rng rng(seed);
    const int course = 12;
    for (int y0 = 0; y0 < h; y0 += course) {
        int x = -int(rng.below(20));
        while (x < w) {
            const int len = 14 + int(rng.below(13));
            const int shade = 150 + int(rng.below(60));
            for (int y = y0; y < std::min(h, y0 + course); ++y)
                for (int xx = std::max(0, x); xx < std::min(w, x + len); ++xx) {
                    const bool mortar = y - y0 >= course - 2 || xx - x >= len - 2;
                    uint8_t* p = img.at(xx, y);
                    const int noise = int(rng.below(9)) - 4;
                    p[0] = uint8_t(mortar ? 50 + noise : shade + noise);
                    p[1] = uint8_t(mortar ? 45 + noise : shade / 2 + noise);
                    p[2] = uint8_t(mortar ? 40 + noise : shade / 3 + noise);
                }
            x += len;
        }
    }
    return img;
}

bool is_mortar(const Image& img, int x, int y) { return img.at(x, y)[0] < 100; }

struct RunStats {
    double mortar_fraction = 0, mean_row_run = 0, mean_column_run = 0;
};

// Mean length of brick runs between mortar pixels along rows and columns
// (runs touching the image's border are left out).
RunStats runs(const Image& img) {
    RunStats s;
    std::size_t mortar = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) mortar += is_mortar(img, x, y);
    s.mortar_fraction = double(mortar) / double(img.pixel_count());
    auto mean_run = [&](bool along_rows) {
        const int lines = along_rows ? img.height : img.width, length = along_rows ? img.width : img.height;
        double total = 0;
        int count = 0;
        for (int l = 0; l < lines; ++l) {
            int start = -1;
            for (int i = 0; i < length; ++i) {
                const bool m = along_rows ? is_mortar(img, i, l) : is_mortar(img, l, i);
                if (m) {
                    if (start >= 0 && i - start > 0) {
                        total += i - start;
                        ++count;
                    }
                    start = i + 1;
                }
            }
        }
        return count ? total / count : 1e9;
    };
    s.mean_row_run = mean_run(true);
    s.mean_column_run = mean_run(false);
    return s;
}

vqtex_synth_params coherent_params(int w, int h, uint64_t seed) {
    vqtex_synth_params p = vqtex_test::default_params(w, h, seed);
    p.engine = VQTEX_ENGINE_COHERENT;
    return p;
}

Image textured(int w, int h, uint64_t seed) {
    Image img(w, h, 3);
    Rng rng(seed);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c)
                img.at(x, y)[c] =
                    uint8_t(int(128 + 60 * std::sin((x + 2 * c) * 0.7) * std::cos(y * 0.45)) + int(rng.below(40)));
    return img;
}

// textured's image with `channels` channels, channel k being its channel
// k mod 3.
Image textured(int w, int h, uint64_t seed, int channels) {
    const Image rgb = textured(w, h, seed);
    Image out(w, h, channels);
    for (std::size_t i = 0; i < out.pixel_count(); ++i)
        for (int k = 0; k < channels; ++k)
            out.pixels[i * std::size_t(channels) + std::size_t(k)] = rgb.pixels[i * 3 + std::size_t(k % 3)];
    return out;
}

}  // namespace

TEST(Coherent, DefaultsSelectTheCoherentEngine) {
    vqtex_synth_params p;
    vqtex_synth_params_init(&p);
    EXPECT_EQ(p.engine, VQTEX_ENGINE_COHERENT);
    EXPECT_GE(p.coherent.coherence, 1u);
    EXPECT_GE(p.coherent.passes, 1u);
}

TEST(Coherent, PrincipalAxesAreOrthonormalAndOrdered) {
    // Samples spread mostly along (1, 1, 0, 0), less along (0, 0, 1, -1),
    // least along (0, 0, 1, 1).
    Rng rng(3);
    const int count = 4000;
    std::vector<int16_t> columns(4 * count);  // principal_axes takes the samples column by column
    for (int i = 0; i < count; ++i) {
        const int a = int(rng.below(201)) - 100, b = (int(rng.below(201)) - 100) / 3,
                  c = (int(rng.below(201)) - 100) / 10;
        int component = 0;
        for (int v : {128 + a, 128 + a, 100 + b + c, 100 - b + c}) columns[component++ * count + i] = int16_t(v);
    }
    const auto axes = principal_axes(columns, 4, count, 4);
    ASSERT_EQ(axes.size(), 4u);
    auto dot = [](const std::vector<int32_t>& u, const std::vector<int32_t>& v) {
        double s = 0;
        for (std::size_t i = 0; i < u.size(); ++i) s += double(u[i]) * v[i];
        return s / (32768.0 * 32768.0);
    };
    for (int i = 0; i < 3; ++i) {
        EXPECT_NEAR(dot(axes[i], axes[i]), 1.0, 1e-3) << i;
        for (int j = 0; j < i; ++j) EXPECT_NEAR(dot(axes[i], axes[j]), 0.0, 1e-3) << i << "," << j;
    }
    const double r = std::sqrt(0.5);
    EXPECT_NEAR(std::abs(dot(axes[0], {int32_t(r * 32768), int32_t(r * 32768), 0, 0})), 1.0, 1e-2);
    EXPECT_NEAR(std::abs(dot(axes[1], {0, 0, int32_t(r * 32768), -int32_t(r * 32768)})), 1.0, 1e-2);
    EXPECT_NEAR(std::abs(dot(axes[2], {0, 0, int32_t(r * 32768), int32_t(r * 32768)})), 1.0, 1e-2);
    // The first two dimensions are equal in every sample: the fourth axis
    // carries no variance; it is zero or any unit vector orthogonal to the rest.
    const double n3 = dot(axes[3], axes[3]);
    EXPECT_TRUE(std::abs(n3) < 1e-9 || std::abs(n3 - 1.0) < 1e-3) << n3;
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(dot(axes[3], axes[j]), 0.0, 1e-3) << j;
}

TEST(Coherent, AppearanceVectorsAreTheCentredWindowsProjectedOnTheAxes) {
    // The definition, pixel by pixel, against the engine's row-wise
    // projection: each level's 5x5 window (taps 2^level apart, read past
    // the edges mirrored or wrapped, even where the taps span the example
    // several times), less the mean window of the samples, projected on the
    // principal axes of those samples, rounded and clamped.
    for (int channels : {1, 3, 4})
        for (bool wraps : {false, true}) {
            Image ex = textured(13, 9, uint64_t(channels) + (wraps ? 10 : 0));
            if (channels != 3) {
                Image other(ex.width, ex.height, channels);
                for (std::size_t i = 0; i < other.pixels.size(); ++i)
                    other.pixels[i] = ex.pixels[(i * 7) % ex.pixels.size()];
                ex = other;
            }
            const int levels = 4, dims = 25 * channels;
            const AppearanceSpace space = build_appearance_space(ex, levels, wraps, 2);
            ASSERT_EQ(space.levels.size(), std::size_t(levels));
            const EdgeMode edges = wraps ? EdgeMode::Wrap : EdgeMode::Mirror;
            for (int l = 0; l < levels; ++l) {
                const Image& img = space.levels[std::size_t(l)].colours;
                const int step = 1 << l;
                auto window = [&](int x, int y) {
                    std::vector<int32_t> v;
                    for (int r = -2; r <= 2; ++r)
                        for (int c = -2; c <= 2; ++c)
                            for (int k = 0; k < channels; ++k)
                                v.push_back(img.at(edge_index(x + c * step, ex.width, edges),
                                                   edge_index(y + r * step, ex.height, edges))[k]);
                    return v;
                };
                // 117 pixels: every one is a sample.
                const int count = ex.width * ex.height;
                std::vector<int16_t> columns(std::size_t(dims) * count);
                std::vector<int64_t> mean(std::size_t(dims), 0);
                for (int y = 0; y < ex.height; ++y)
                    for (int x = 0; x < ex.width; ++x) {
                        const std::vector<int32_t> v = window(x, y);
                        for (int i = 0; i < dims; ++i) {
                            columns[std::size_t(i) * count + std::size_t(y * ex.width + x)] =
                                int16_t(v[std::size_t(i)]);
                            mean[std::size_t(i)] += v[std::size_t(i)];
                        }
                    }
                for (auto& m : mean) m = (m + count / 2) / count;
                const auto axes = principal_axes(columns, dims, count, kAppearanceDims);
                for (int y = 0; y < ex.height; ++y)
                    for (int x = 0; x < ex.width; ++x) {
                        const std::vector<int32_t> v = window(x, y);
                        for (int a = 0; a < kAppearanceDims; ++a) {
                            int64_t sum = 0;
                            for (int i = 0; i < dims; ++i)
                                sum += int64_t(axes[std::size_t(a)][std::size_t(i)]) *
                                       (v[std::size_t(i)] - mean[std::size_t(i)]);
                            const int64_t expected =
                                std::clamp<int64_t>((sum + (1 << 14)) >> 15, -kAppearanceClamp, kAppearanceClamp);
                            ASSERT_EQ(space.feature(l, x, y)[a], expected)
                                << channels << " channels, wraps " << wraps << ", level " << l << " at " << x << ","
                                << y;
                        }
                    }
            }
        }
}

TEST(Coherent, CoherenceSetsEqualBruteForce) {
    const Image ex = textured(26, 21, 5);
    const AppearanceSpace space = build_appearance_space(ex, 3, false, 1);
    const int k = 4, exclusion = 2;
    const CoherenceSets sets = build_coherence_sets(space, k, exclusion, 2);
    ASSERT_EQ(sets.levels.size(), 3u);
    const int n = ex.width * ex.height;
    for (int l = 0; l < 3; ++l) {
        const int reach = exclusion * space.levels[l].spacing;
        for (int u = 0; u < n; ++u) {
            const int16_t* fu = space.levels[l].features.data() + std::size_t(u) * kAppearanceDims;
            std::vector<std::pair<int64_t, int>> all;
            for (int c = 0; c < n; ++c) {
                if (std::abs(c % ex.width - u % ex.width) < reach && std::abs(c / ex.width - u / ex.width) < reach)
                    continue;
                const int16_t* fc = space.levels[l].features.data() + std::size_t(c) * kAppearanceDims;
                int64_t d = 0;
                for (int i = 0; i < kAppearanceDims; ++i) d += int64_t(fu[i] - fc[i]) * (fu[i] - fc[i]);
                all.push_back({d, c});
            }
            std::sort(all.begin(), all.end());
            const uint32_t* set = sets.of(l, uint32_t(u));
            ASSERT_EQ(set[0], uint32_t(u));
            for (int i = 1; i < k; ++i)
                ASSERT_EQ(set[i], uint32_t(all[std::size_t(i - 1)].second)) << l << " " << u << " " << i;
        }
    }
}

// The copy relocation (copy_relocation.hpp) moves each copy whole: every
// pixel of a copy by the same translation, inside the example; a copy
// covering half the level stays; no positions tried, nothing moves; and
// the map is the same for any thread count.
TEST(Coherent, RelocationMovesWholeCopiesInsideTheExample) {
    const Image ex = textured(48, 40, 3);
    const AppearanceSpace space = build_appearance_space(ex, 3, false, 1);
    const int level = 1, s = space.levels[level].spacing;
    ASSERT_EQ(s, 2);
    // Three copies that do not continue one another: A, the left 14
    // columns (more than half the map), and B and C, the top and bottom
    // halves of the rest.
    PositionMap map{24, 20, std::vector<uint32_t>(24 * 20)};
    std::vector<int> copy_of(map.positions.size());
    for (int y = 0; y < 20; ++y)
        for (int x = 0; x < 24; ++x) {
            const std::size_t i = std::size_t(y) * 24 + std::size_t(x);
            copy_of[i] = x < 14 ? 0 : y < 10 ? 1 : 2;
            map.positions[i] = copy_of[i] == 0   ? pack_position(1 + x * s, y * s)
                               : copy_of[i] == 1 ? pack_position(5 + (x - 14) * s, 3 + y * s)
                                                 : pack_position(20 + (x - 14) * s, 7 + (y - 10) * s);
        }
    PositionMap none = map;
    relocate_copies(space, level, none, 0, 7, 1);
    EXPECT_EQ(none.positions, map.positions);
    PositionMap one = map, three = map;
    relocate_copies(space, level, one, 64, 7, 1);
    relocate_copies(space, level, three, 64, 7, 3);
    EXPECT_EQ(one.positions, three.positions);
    int moved_copies = 0;
    for (int c = 0; c < 3; ++c) {
        bool first = true;
        int dx = 0, dy = 0;
        for (std::size_t i = 0; i < map.positions.size(); ++i) {
            if (copy_of[i] != c) continue;
            const uint32_t after = one.positions[i];
            ASSERT_LT(position_x(after), ex.width);
            ASSERT_LT(position_y(after), ex.height);
            const int ddx = position_x(after) - position_x(map.positions[i]);
            const int ddy = position_y(after) - position_y(map.positions[i]);
            if (first) {
                dx = ddx;
                dy = ddy;
                first = false;
            }
            ASSERT_EQ(ddx, dx) << "copy " << c << " pixel " << i;
            ASSERT_EQ(ddy, dy) << "copy " << c << " pixel " << i;
        }
        if (c == 0) {
            EXPECT_TRUE(dx == 0 && dy == 0) << "the copy covering half the map moved";
        }
        moved_copies += dx != 0 || dy != 0;
    }
    EXPECT_GT(moved_copies, 0) << "no copy found a better place among 64";
}

// Format 7's edge guard (docs/FORMAT.md §4.7-§4.8): where a copy
// runs into the example's edge, the pixel beside it must not show the same
// columns or rows again a few pixels back (a stutter): the finest level's
// pairs of neighbours where one's copy would go on past the edge and the
// other sits within 8 pixels of where it would have gone. Without the
// guard this example has such pairs; with it, a small fraction of them,
// and the map is the same for any thread count.
TEST(Coherent, EdgeGuardEndsCopiesCutOffByTheEdgeInSeams) {
    const Image ex = textured(48, 40, 3);
    const AppearanceSpace space = build_appearance_space(ex, 4, false, 1);
    const CoherenceSets sets = build_coherence_sets(space, 1, kCoherenceExclusion, 1);
    const auto stutters = [&](const PositionMap& m) {
        int count = 0;
        for (int y = 0; y < m.height; ++y)
            for (int x = 0; x < m.width; ++x)
                for (int d = 0; d < 4; ++d) {
                    const int dx = d == 0 ? 1 : d == 1 ? -1 : 0, dy = d == 2 ? 1 : d == 3 ? -1 : 0;
                    const uint32_t p = m.positions[std::size_t(y) * m.width + x];
                    const uint32_t q = m.positions[std::size_t(Image::wrap(y + dy, m.height)) * m.width +
                                                   std::size_t(Image::wrap(x + dx, m.width))];
                    const int cx = position_x(p) + dx, cy = position_y(p) + dy;
                    if (cx >= 0 && cy >= 0 && cx < ex.width && cy < ex.height) continue;
                    count += std::abs(position_x(q) - cx) < 8 && std::abs(position_y(q) - cy) < 8;
                }
        return count;
    };
    const auto map_with = [&](int guard, int threads) {
        CoherentOptions o;
        o.width = 150;
        o.height = 130;
        o.seed = 3;
        o.threads = threads;
        o.relocate = 64;
        o.edge_guard = guard;
        return synthesize_positions(space, sets, o);
    };
    const PositionMap without = map_with(0, 1), with = map_with(8, 1);
    const int before = stutters(without), after = stutters(with);
    EXPECT_GT(before, 10) << "the example should stutter at its edges without the guard";
    EXPECT_LT(4 * after, before) << "with the guard: " << after << ", without: " << before;
    EXPECT_EQ(map_with(8, 3).positions, with.positions);
}

TEST(Coherent, UpsampledChildrenAreCoherentBlocksInsideTheExample) {
    const Image ex = textured(40, 33, 2);
    const AppearanceSpace space = build_appearance_space(ex, 3, false, 1);
    for (int spacing : {1, 2, 4}) {
        PositionMap parent{7, 5, {}};
        Rng rng{uint64_t(spacing)};
        for (int i = 0; i < 35; ++i) parent.positions.push_back(pack_position(int(rng.below(40)), int(rng.below(33))));
        const PositionMap child = upsample_positions(space, parent, 13, 10, spacing);
        ASSERT_EQ(child.positions.size(), 130u);
        for (int y = 0; y < 10; ++y)
            for (int x = 0; x < 13; ++x) {
                const uint32_t p = parent.positions[std::size_t(y / 2) * 7 + x / 2];
                const uint32_t c = child.positions[std::size_t(y) * 13 + x];
                ASSERT_LT(position_x(c), 40);
                ASSERT_LT(position_y(c), 33);
                // The definition: the parent's position plus the child's
                // offset, or the block moved inside when it would cross the edge.
                const int bx = position_x(p) + spacing < 40 ? position_x(p) : 40 - 1 - spacing;
                const int by = position_y(p) + spacing < 33 ? position_y(p) : 33 - 1 - spacing;
                EXPECT_EQ(position_x(c), bx + (x & 1) * spacing);
                EXPECT_EQ(position_y(c), by + (y & 1) * spacing);
            }
    }
}

TEST(Coherent, SameBytesForAnyThreadCountAndRun) {
    const Image ex = brick_wall(96, 96, 7);
    vqtex_synth_params p = coherent_params(150, 110, 9);
    const Image one = vqtex_test::synthesize(ex, p);
    for (uint32_t threads : {2u, 3u, 5u}) {
        p.threads = threads;
        EXPECT_EQ(vqtex_test::synthesize(ex, p), one) << threads;
    }
}

TEST(Coherent, SeedsGiveDifferentTextures) {
    const Image ex = brick_wall(96, 96, 7);
    const Image a = vqtex_test::synthesize(ex, coherent_params(128, 128, 1));
    const Image b = vqtex_test::synthesize(ex, coherent_params(128, 128, 2));
    std::size_t differing = 0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i) differing += a.pixels[i] != b.pixels[i];
    EXPECT_GT(differing, a.pixels.size() / 2);
}

TEST(Coherent, BrickStructureReproduced) {
    // Courses and brick lengths keep their sizes: mean brick runs along
    // rows and columns, and the share of mortar, within 15% of the example's.
    const Image ex = brick_wall(128, 128, 11);
    const RunStats want = runs(ex);
    for (uint64_t seed : {1u, 2u, 3u}) {
        const Image out = vqtex_test::synthesize(ex, coherent_params(256, 256, seed));
        const RunStats got = runs(out);
        EXPECT_NEAR(got.mortar_fraction, want.mortar_fraction, 0.15 * want.mortar_fraction) << seed;
        EXPECT_NEAR(got.mean_row_run, want.mean_row_run, 0.15 * want.mean_row_run) << seed;
        EXPECT_NEAR(got.mean_column_run, want.mean_column_run, 0.15 * want.mean_column_run) << seed;
    }
}

TEST(Coherent, EveryOutputPixelIsAnExamplePixel) {
    // Coordinates synthesis without a blend copies pixels: no colour the
    // example lacks, hence no blur and no invented noise.
    const Image ex = textured(64, 48, 4);
    vqtex_synth_params params = coherent_params(100, 70, 3);
    params.coherent.blend = 0;
    const Image out = vqtex_test::synthesize(ex, params);
    std::vector<uint32_t> colours;
    for (int y = 0; y < ex.height; ++y)
        for (int x = 0; x < ex.width; ++x) {
            const uint8_t* p = ex.at(x, y);
            colours.push_back(uint32_t(p[0]) << 16 | uint32_t(p[1]) << 8 | p[2]);
        }
    std::sort(colours.begin(), colours.end());
    for (int y = 0; y < out.height; ++y)
        for (int x = 0; x < out.width; ++x) {
            const uint8_t* p = out.at(x, y);
            ASSERT_TRUE(
                std::binary_search(colours.begin(), colours.end(), uint32_t(p[0]) << 16 | uint32_t(p[1]) << 8 | p[2]));
        }
}

TEST(Coherent, InvalidParametersRefused) {
    const Image ex = textured(32, 32, 1);
    vqtex_image in{32, 32, 3, const_cast<uint8_t*>(ex.pixels.data())};
    vqtex_image out{};
    vqtex_error err{};
    for (auto tweak :
         {+[](vqtex_synth_params& p) { p.coherent.coherence = 0; }, +[](vqtex_synth_params& p) { p.coherent.coherence = 17; },
          +[](vqtex_synth_params& p) { p.coherent.passes = 0; }, +[](vqtex_synth_params& p) { p.coherent.jitter = 1025; },
          +[](vqtex_synth_params& p) { p.coherent.blend = 4; }, +[](vqtex_synth_params& p) { p.coherent.relocate = 1025; },
          +[](vqtex_synth_params& p) { p.coherent.edge_guard = 65; },
          +[](vqtex_synth_params& p) { p.engine = vqtex_engine(7); }}) {
        vqtex_synth_params p = coherent_params(32, 32, 1);
        tweak(p);
        EXPECT_EQ(vqtex_synthesize(&p, &in, &out, nullptr, &err), VQTEX_ERROR_INVALID_ARGUMENT);
        EXPECT_EQ(out.pixels, nullptr);
    }
}

TEST(Coherent, TinyExamplesAndOutputs) {
    for (int side : {1, 2, 5, 9}) {
        const Image ex = textured(side, side + 1, 1);
        for (int out_side : {1, 3, 17}) {
            const Image out = vqtex_test::synthesize(ex, coherent_params(out_side, out_side + 2, 1));
            EXPECT_EQ(out.width, out_side);
            EXPECT_EQ(out.height, out_side + 2);
        }
    }
}

TEST(Coherent, GoldenHash) {
    // The engine's bytes pinned across builds, compilers and kernel sets
    // (the simd_whole_decode test forces each set): a change of this hash
    // is a change of every output, to be made on purpose and noted.
    // Without the blend, the relocation and the edge guard, the positions'
    // pixels as before either existed; with the blend alone, as before the
    // relocation; with the blend and the relocation, as before the edge
    // guard; with those and the edge guard, as before the cuts; with those
    // and the cuts, as before the covers; with the defaults, what the
    // engine gives now.
    const Image ex = brick_wall(96, 96, 7);
    const auto hash_of = [&](uint32_t blend, uint32_t relocate, uint32_t edge_guard = 0, uint32_t cut = 0,
                             uint32_t margin = 0, uint32_t cover = 0) {
        vqtex_synth_params p = coherent_params(150, 110, 9);
        p.coherent.blend = blend;
        p.coherent.relocate = relocate;
        p.coherent.edge_guard = edge_guard;
        p.coherent.cut = cut;
        p.coherent.margin = margin;
        p.coherent.cover = cover;
        uint64_t h = 0xcbf29ce484222325ull;
        for (uint8_t v : vqtex_test::synthesize(ex, p).pixels) h = (h ^ v) * 0x100000001b3ull;
        return h;
    };
    EXPECT_EQ(hash_of(0, 0), 0x217a760a4b8cbd8dull) << std::hex << hash_of(0, 0);
    EXPECT_EQ(hash_of(2, 0), 0xe57f22f79c9296b9ull) << std::hex << hash_of(2, 0);
    EXPECT_EQ(coherent_params(1, 1, 1).coherent.blend, 2u);
    EXPECT_EQ(coherent_params(1, 1, 1).coherent.relocate, 64u);
    EXPECT_EQ(hash_of(2, 64), 0x83b06954069c3180ull) << std::hex << hash_of(2, 64);
    EXPECT_EQ(coherent_params(1, 1, 1).coherent.edge_guard, 8u);
    EXPECT_EQ(hash_of(2, 64, 8), 0xc49dfaedd9457d81ull) << std::hex << hash_of(2, 64, 8);
    EXPECT_EQ(coherent_params(1, 1, 1).coherent.cut, 8u);
    EXPECT_EQ(hash_of(2, 64, 8, 8), 0xc43e8f3bdf8f3649ull) << std::hex << hash_of(2, 64, 8, 8);
    EXPECT_EQ(coherent_params(1, 1, 1).coherent.margin, 0u);
    EXPECT_EQ(hash_of(2, 64, 8, 8, 2), 0x5039d1d8e6aa8c0bull) << std::hex << hash_of(2, 64, 8, 8, 2);
    EXPECT_EQ(coherent_params(1, 1, 1).coherent.cover, 8u);
    EXPECT_EQ(hash_of(2, 64, 8, 8, 0, 8), 0x88c838726cbcbe1eull) << std::hex << hash_of(2, 64, 8, 8, 0, 8);
    EXPECT_NE(hash_of(2, 64, 8, 8, 0, 8), hash_of(2, 64, 8, 8)) << "the covers changed nothing here";
}

// docs/FORMAT.md §4.12's blend, as written there, for pixel (x, y) of a map.
std::vector<uint8_t> reference_blend(const Image& ex, bool wraps, int r, const PositionMap& map, int x, int y) {
    static const int weights[4][7] = {{1}, {1, 2, 1}, {1, 4, 6, 4, 1}, {1, 6, 15, 20, 15, 6, 1}};
    uint64_t sum[4] = {0, 0, 0, 0}, total = 0;
    for (int dy = -r; dy <= r; ++dy)
        for (int dx = -r; dx <= r; ++dx) {
            const uint32_t q =
                map.positions[std::size_t(Image::wrap(y + dy, map.height)) * map.width + Image::wrap(x + dx, map.width)];
            int sx = position_x(q) - dx, sy = position_y(q) - dy;
            if (wraps) {
                sx = Image::wrap(sx, ex.width);
                sy = Image::wrap(sy, ex.height);
            } else if (sx < 0 || sy < 0 || sx >= ex.width || sy >= ex.height) {
                continue;
            }
            const uint64_t weight = uint64_t(weights[r][dx + r] * weights[r][dy + r]);
            for (int c = 0; c < ex.channels; ++c) sum[c] += weight * ex.at(sx, sy)[c];
            total += weight;
        }
    std::vector<uint8_t> out(std::size_t(ex.channels));
    for (int c = 0; c < ex.channels; ++c) out[std::size_t(c)] = uint8_t((sum[c] + total / 2) / total);
    return out;
}

TEST(Coherent, BlendIsTheFormatsWeightedMeanAndChangesOnlySeams) {
    // Every pixel against FORMAT.md §4.12's procedure, on synthesised maps
    // (copies and seams as the engine makes them) and on maps of random
    // positions (every window a seam): mirrored and tileable examples,
    // 1 to 4 channels, every radius, outputs and examples narrower than a
    // window, 1 and 3 threads. Where the whole window continues one copy
    // the pixel is that copy's, so a blend changes only seams.
    struct Case {
        int ew, eh, channels, w, h;
        bool tileable, synthesised;
    };
    const Case cases[] = {{40, 36, 3, 57, 43, false, true}, {40, 36, 3, 57, 43, true, true},
                          {33, 29, 1, 31, 40, false, true}, {12, 10, 4, 20, 9, true, false},
                          {5, 3, 2, 3, 2, false, false},    {2, 7, 3, 1, 6, true, false}};
    for (const Case& c : cases) {
        const Image ex = textured(c.ew, c.eh, 4, c.channels);
        PositionMap map;
        if (c.synthesised) {
            const AppearanceSpace space = build_appearance_space(ex, 3, c.tileable, 1);
            const CoherenceSets sets = build_coherence_sets(space, 1, 2, 1);
            CoherentOptions options;
            options.width = c.w;
            options.height = c.h;
            options.seed = 5;
            map = synthesize_positions(space, sets, options);
        } else {
            map = PositionMap{c.w, c.h, std::vector<uint32_t>(std::size_t(c.w) * c.h)};
            Rng rng(uint64_t(c.w * 131 + c.h));
            for (uint32_t& p : map.positions) p = pack_position(int(rng.next() % uint64_t(c.ew)), int(rng.next() % uint64_t(c.eh)));
        }
        const Image plain = read_positions(ex, PositionMap(map), false, 1, 0, c.tileable);
        for (int r = 1; r <= vqtex::kMaxBlendRadius; ++r)
            for (int threads : {1, 3}) {
                const Image blended = read_positions(ex, PositionMap(map), false, threads, r, c.tileable);
                const std::string what = std::to_string(c.ew) + "x" + std::to_string(c.eh) + "x" +
                                         std::to_string(c.channels) + (c.tileable ? " tileable" : " mirrored") +
                                         ", output " + std::to_string(c.w) + "x" + std::to_string(c.h) + ", radius " +
                                         std::to_string(r) + ", " + std::to_string(threads) + " threads";
                int seams = 0, changed = 0;
                for (int y = 0; y < map.height; ++y)
                    for (int x = 0; x < map.width; ++x) {
                        const std::vector<uint8_t> want = reference_blend(ex, c.tileable, r, map, x, y);
                        ASSERT_EQ(std::memcmp(blended.at(x, y), want.data(), want.size()), 0)
                            << what << " at " << x << "," << y;
                        const uint32_t own = map.positions[std::size_t(y) * map.width + x];
                        bool one_copy = true;
                        for (int dy = -r; dy <= r; ++dy)
                            for (int dx = -r; dx <= r; ++dx)
                                one_copy = one_copy &&
                                           map.positions[std::size_t(Image::wrap(y + dy, map.height)) * map.width +
                                                         Image::wrap(x + dx, map.width)] ==
                                               pack_position(position_x(own) + dx, position_y(own) + dy) &&
                                           position_x(own) + dx >= 0 && position_x(own) + dx < c.ew &&
                                           position_y(own) + dy >= 0 && position_y(own) + dy < c.eh;
                        if (one_copy) {
                            ASSERT_EQ(std::memcmp(blended.at(x, y), plain.at(x, y), std::size_t(c.channels)), 0)
                                << what << " at " << x << "," << y;
                        } else {
                            ++seams;
                            changed += std::memcmp(blended.at(x, y), plain.at(x, y), std::size_t(c.channels)) != 0;
                        }
                    }
                EXPECT_GT(seams, 0) << what;
                EXPECT_GT(changed, 0) << what;
            }
    }
}

TEST(Coherent, PixelIndicesKeepEveryPositionInTwoThreeOrFourBytes) {
    EXPECT_EQ(PixelIndices::bytes_for(1), 2);
    EXPECT_EQ(PixelIndices::bytes_for(65536), 2);
    EXPECT_EQ(PixelIndices::bytes_for(65537), 3);
    EXPECT_EQ(PixelIndices::bytes_for(uint64_t(1) << 24), 3);
    EXPECT_EQ(PixelIndices::bytes_for((uint64_t(1) << 24) + 1), 4);
    // Examples of 256x256, 4096x4096 and 8192x4096 pixels: the corners and
    // positions whose every byte of index is set.
    struct Case {
        int width, height, bytes;
    };
    for (const Case& c : {Case{256, 256, 2}, Case{4096, 4096, 3}, Case{8192, 4096, 4}}) {
        std::vector<uint32_t> positions = {pack_position(0, 0), pack_position(c.width - 1, 0),
                                           pack_position(0, c.height - 1), pack_position(c.width - 1, c.height - 1),
                                           pack_position(c.width / 3, c.height / 2 + 1)};
        const std::vector<uint32_t> kept = positions;
        const PixelIndices narrow =
            narrow_positions(c.width, uint64_t(c.width) * uint64_t(c.height), positions, 2);
        EXPECT_TRUE(positions.empty());
        EXPECT_EQ(narrow.bytes, c.bytes);
        EXPECT_EQ(narrow.data.size(), kept.size() * std::size_t(c.bytes));
        for (std::size_t i = 0; i < kept.size(); ++i) {
            EXPECT_EQ(narrow.position(i), kept[i]) << c.width << "x" << c.height << " entry " << i;
            EXPECT_EQ(narrow.index(i), uint32_t(position_y(kept[i])) * uint32_t(c.width) + uint32_t(position_x(kept[i])));
        }
    }
}

// With straight alpha (format version 8's blend), a seam between an opaque
// red copy and a transparent black one keeps every visible pixel red: the
// transparent copy's colour has no weight. Blending every channel alike
// (versions 5 to 7) darkens the partly transparent pixels toward black.
TEST(Coherent, BlendWeightsColourByStraightAlpha) {
    const uint8_t red[4] = {230, 40, 20, 255};
    Image ex(32, 16, 4);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) std::copy(red, red + 4, ex.at(x, y));  // the right half stays 0, 0, 0, 0
    PositionMap map{24, 8, std::vector<uint32_t>(24 * 8)};
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 24; ++x)
            map.positions[std::size_t(y) * 24 + x] = x < 12 ? pack_position(2 + x, 4 + y) : pack_position(6 + x, 4 + y);
    for (int r = 1; r <= vqtex::kMaxBlendRadius; ++r) {
        const Image straight = read_positions(ex, PositionMap(map), false, 1, r, false, true);
        const Image alike = read_positions(ex, PositionMap(map), false, 1, r, false, false);
        int partial = 0, darkest = 255;
        for (int y = 0; y < 8; ++y)
            for (int x = 0; x < 24; ++x) {
                const uint8_t* s = straight.at(x, y);
                EXPECT_EQ(s[3], alike.at(x, y)[3]) << "alpha at " << x << "," << y;
                if (s[3] == 0) continue;
                partial += s[3] < 255;
                for (int c = 0; c < 3; ++c) EXPECT_EQ(s[c], red[c]) << "radius " << r << " at " << x << "," << y;
                darkest = std::min(darkest, int(alike.at(x, y)[0]));
            }
        EXPECT_GT(partial, 0) << "radius " << r;
        EXPECT_LT(darkest, 200) << "radius " << r;
    }
}

TEST(Coherent, BandsGiveTheBytesOfTheWholeLevel) {
    // A large output's finest level runs in bands of rows with margins
    // (the decoder's memory budget, docs/PERFORMANCE.md); any band height, odd heights among them
    // (the subsets' parity across the torus's wrap), 1 to 3 channels, jitter,
    // more passes, no polish, no roll, k > 1, a tileable example, the edge
    // guard, the cuts between copies (whose blocks of rows a band must hold
    // whole: outputs tall enough to be cut into bands at all), and any
    // thread count must give the bytes of the whole level.
    struct Case {
        int w, h, channels, passes, polish, jitter, coherence;
        bool roll, tileable;
        int blend;
        int example_w = 40, example_h = 36;
        int edge_guard = 8;
        int cut = 0;
        int margin = 0;
        int cover = 0;
    };
    // The last example has more than 65536 pixels: the coarser level's
    // positions are kept as 3-byte indices.
    const Case cases[] = {{61, 97, 1, 2, 1, 0, 1, true, false, 0},  {40, 121, 2, 2, 1, 0, 1, true, false, 2},
                          {33, 80, 3, 2, 1, 64, 1, true, false, 3}, {50, 99, 1, 3, 2, 0, 3, false, false, 1},
                          {47, 60, 3, 1, 0, 0, 1, true, true, 2},   {45, 70, 1, 2, 1, 0, 1, true, false, 2, 300, 230},
                          {52, 90, 3, 2, 1, 0, 1, true, false, 2, 40, 36, 0},
                          {40, 263, 3, 2, 1, 0, 1, true, false, 2, 40, 36, 8, 8, 2},
                          {37, 290, 1, 2, 1, 0, 1, true, true, 2, 40, 36, 8, 16},
                          {44, 270, 2, 2, 1, 0, 2, true, false, 1, 48, 40, 8, 6, 3},
                          // The covers over long borders (whose blocks and
                          // competing covers a band must hold whole too).
                          {40, 600, 3, 2, 1, 0, 1, true, false, 2, 40, 36, 8, 8, 0, 8},
                          {37, 700, 1, 2, 1, 0, 1, true, true, 2, 40, 36, 8, 8, 0, 12}};
    for (const Case& c : cases) {
        const Image ex = textured(c.example_w, c.example_h, 3, c.channels);
        CoherentOptions options;
        options.width = c.w;
        options.height = c.h;
        options.seed = 4;
        options.passes = c.passes;
        options.polish_passes = c.polish;
        options.jitter = c.jitter;
        options.roll = c.roll;
        options.blend = c.blend;
        options.edge_guard = c.edge_guard;
        options.cut = c.cut;
        options.margin = c.margin;
        options.cover = c.cover;
        const std::string what = std::to_string(c.w) + "x" + std::to_string(c.h) + "x" + std::to_string(c.channels) +
                                 " blend " + std::to_string(c.blend) + " edge guard " + std::to_string(c.edge_guard) +
                                 " cut " + std::to_string(c.cut) + " margin " + std::to_string(c.margin) + " cover " +
                                 std::to_string(c.cover);
        const Image whole = synthesize_coherent(ex, 4, c.tileable, c.coherence, options).image;
        if (c.cover > 0) {
            // (The covers must do something here, or the case shows nothing.)
            options.cover = 0;
            EXPECT_NE(synthesize_coherent(ex, 4, c.tileable, c.coherence, options).image, whole) << what;
            options.cover = c.cover;
        }
        for (int band : {1, 2, 7, 16}) {
            // (The covers' cases are 600 rows and more, each band with
            // about 280 rows of margin on either side: bands of 1 and 2
            // rows would run the whole level a few hundred times over.)
            if (c.cover > 0 && band < 7) continue;
            options.band_rows = band;
            options.threads = 1 + band % 3;
            EXPECT_EQ(synthesize_coherent(ex, 4, c.tileable, c.coherence, options).image, whole) << what << " band " << band;
        }
    }
}

TEST(Coherent, AnalysisLevelByLevelGivesTheBytesOfTheWholeStack) {
    // A large example's appearance vectors and coherence sets are made one
    // level at a time, as the synthesis reaches each level (and the finest
    // before its bands): the same vectors, so the same output, for k = 1
    // and k > 1, mirrored and tileable, whole and in bands, on 1 and 2
    // threads.
    struct Case {
        int channels, coherence, band_rows;
        bool tileable;
    };
    const Case cases[] = {{3, 1, 0, false}, {1, 2, 0, true}, {3, 3, 5, false}, {2, 1, 7, true}};
    for (const Case& c : cases) {
        const Image ex = textured(45, 38, 3, c.channels);
        CoherentOptions options;
        options.width = 70;
        options.height = 66;
        options.seed = 9;
        options.band_rows = c.band_rows;
        options.analysis_by_level = 0;
        const CoherentResult at_once = synthesize_coherent(ex, 4, c.tileable, c.coherence, options);
        const std::string what = std::to_string(c.channels) + " channels, k " + std::to_string(c.coherence);
        for (int threads : {1, 2}) {
            options.analysis_by_level = 1;
            options.threads = threads;
            const CoherentResult by_level = synthesize_coherent(ex, 4, c.tileable, c.coherence, options);
            EXPECT_EQ(by_level.image, at_once.image) << what << ", " << threads << " threads";
        }
    }
    // Left to its size, an example is analysed level by level when its
    // vectors would exceed 4 MiB (FORMAT.md §4.1's M): 256x256 x 4 levels x
    // 16 bytes is 4 MiB exactly.
    EXPECT_FALSE(analysis_by_level(128, 128, 6));
    EXPECT_FALSE(analysis_by_level(256, 256, 4));
    EXPECT_TRUE(analysis_by_level(256, 256, 5));
    EXPECT_TRUE(analysis_by_level(512, 512, 8));
}

TEST(Coherent, TileableExampleKeepsItsPeriod) {
    // A tileable checkerboard of period 16 (with noise, so that positions
    // are told apart). Read as tileable, copies wrap around the example's
    // edges and the output keeps the period nearly everywhere; read mirrored,
    // far less (measured: 0.87 and 0.74 of the pixels agree with the pixel a
    // period away; 0.5 would be no period at all). Where it breaks, copies of
    // two phases meet: the coarsest levels (spacing 16) see the pattern
    // blurred flat and cannot choose one phase.
    Image ex(64, 64, 3);
    Rng rng(8);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x)
            for (int c = 0; c < 3; ++c)
                ex.at(x, y)[c] = uint8_t((((x / 8) + (y / 8)) % 2 ? 200 : 60) + int(rng.below(20)));
    auto agreement = [&](bool tileable) {
        vqtex_synth_params p = coherent_params(160, 144, 5);
        p.example_tileable = tileable ? 1 : 0;
        // The copy relocation leaves a tileable example's copies alone (they
        // wrap); off for both, the two engines compared are the same one.
        p.coherent.relocate = 0;
        const Image out = vqtex_test::synthesize(ex, p);
        std::size_t same = 0;
        for (int y = 0; y < out.height; ++y)
            for (int x = 0; x < out.width; ++x) same += (out.at(x, y)[0] >= 128) == (out.wrapped(x + 16, y)[0] >= 128);
        return double(same) / double(out.pixel_count());
    };
    const double wrapped = agreement(true), mirrored = agreement(false);
    EXPECT_GT(wrapped, 0.85);
    EXPECT_GT(wrapped, mirrored + 0.08);
}

namespace {

// The definition of one correction of pixel (x, y), written plainly: the
// candidates are the pixel's own position, then, in raster order of the 5x5
// neighbours, each neighbour's source shifted back by its offset (when that
// stays inside the example); the winner has the least full distance between
// the 5x5 windows of appearance vectors, weighed by its broken links, the
// earliest candidate on ties. With an edge guard (format 7), a position
// closer than `guard` in x and y to where a nearest neighbour's copy would
// go on past the example's edge is barred as a repeat is.
uint32_t reference_correction(const AppearanceSpace& space, int level, const PositionMap& map, int x, int y,
                              int guard = 0) {
    const int s = space.levels[std::size_t(level)].spacing;
    auto source = [&](int dx, int dy) {
        return map.positions[std::size_t(Image::wrap(y + dy, map.height)) * map.width + Image::wrap(x + dx, map.width)];
    };
    auto distance = [&](uint32_t c) {
        int64_t d = 0;
        for (int dy = -2; dy <= 2; ++dy)
            for (int dx = -2; dx <= 2; ++dx) {
                const uint32_t q = source(dx, dy);
                const int16_t* fq = space.feature(level, position_x(q), position_y(q));
                const int16_t* fc =
                    space.feature(level, space.fold_x(position_x(c) + dx * s), space.fold_y(position_y(c) + dy * s));
                for (int i = 0; i < kAppearanceDims; ++i) d += int64_t(fq[i] - fc[i]) * (fq[i] - fc[i]);
            }
        return d;
    };
    // A position one of the four nearest neighbours holds would repeat a
    // pixel: never a candidate, and the pixel's own loses to any other.
    auto next_door = [&](uint32_t c) {
        if (c == source(0, -1) || c == source(-1, 0) || c == source(1, 0) || c == source(0, 1)) return true;
        for (const auto& [dx, dy] : {std::pair{0, -1}, std::pair{-1, 0}, std::pair{1, 0}, std::pair{0, 1}}) {
            const int cx = position_x(source(dx, dy)) - dx * s, cy = position_y(source(dx, dy)) - dy * s;
            const bool past_the_edge = cx < 0 || cy < 0 || cx >= space.width || cy >= space.height;
            if (past_the_edge && std::abs(position_x(c) - cx) < guard && std::abs(position_y(c) - cy) < guard)
                return true;
        }
        return false;
    };
    const uint32_t own = source(0, 0);
    std::vector<uint32_t> candidates;
    for (int dy = -2; dy <= 2; ++dy)
        for (int dx = -2; dx <= 2; ++dx) {
            const uint32_t q = source(dx, dy);
            const int ux = position_x(q) - dx * s, uy = position_y(q) - dy * s;
            const uint32_t c = pack_position(ux, uy);
            if (ux >= 0 && uy >= 0 && ux < space.width && uy < space.height && c != own && !next_door(c))
                candidates.push_back(c);
        }
    // Each of the four nearest neighbours that does not continue the
    // candidate's copy adds its distance once more (link bias 256/256).
    auto weighed = [&](uint32_t c) {
        const int cx = position_x(c), cy = position_y(c);
        int broken = 0;
        broken += source(0, -1) != pack_position(cx, cy - s);
        broken += source(0, 1) != pack_position(cx, cy + s);
        broken += source(-1, 0) != pack_position(cx - s, cy);
        broken += source(1, 0) != pack_position(cx + s, cy);
        return distance(c) * (1 + broken);
    };
    // The pixel's own position first; barred, it loses to any candidate.
    uint32_t best = own;
    int64_t best_d = next_door(own) ? INT64_MAX : weighed(own);
    for (uint32_t c : candidates)
        if (const int64_t d = weighed(c); d < best_d) best = c, best_d = d;
    return best;
}

}  // namespace

TEST(Coherent, CorrectionEqualsItsDefinition) {
    // Random positions (many candidates per pixel, ties included), on a
    // small example and an odd-sized torus: one correction pass of the engine
    // (four interleaved subsets, each reading the state before it) against
    // the definition applied subset by subset.
    // With the edge guard off (formats 3 to 6) and on (format 7: random
    // positions put many beside the edge).
    const Image ex = textured(30, 26, 6);
    const AppearanceSpace space = build_appearance_space(ex, 3, false, 1);
    const CoherenceSets sets = build_coherence_sets(space, 1, 2, 1);
    for (int guard : {0, 3, 8})
        for (int level = 0; level < 3; ++level) {
            PositionMap map{13, 11, {}};
            Rng rng{uint64_t(level + 1)};
            for (int i = 0; i < 13 * 11; ++i)
                map.positions.push_back(pack_position(int(rng.below(30)), int(rng.below(26))));
            PositionMap expected = map;
            static constexpr int kOrder[4][2] = {{0, 0}, {1, 1}, {1, 0}, {0, 1}};
            for (const auto& [sx, sy] : kOrder) {
                const PositionMap before = expected;
                for (int y = sy; y < map.height; y += 2)
                    for (int x = sx; x < map.width; x += 2)
                        expected.positions[std::size_t(y) * map.width + x] =
                            reference_correction(space, level, before, x, y, guard);
            }
            CoherentOptions options;
            options.threads = 2;
            options.edge_guard = guard;
            correct_positions(space, sets, level, map, options);
            EXPECT_EQ(map.positions, expected.positions) << "level " << level << ", edge guard " << guard;
        }
}

// test_tsvq.cpp - TSVQ training and search (paper section 4): the tree has
// the requested size, training is deterministic for any thread count, full
// backtracking equals exhaustive search, and a full codebook reproduces
// exhaustive synthesis bit for bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "dsp/dsp.hpp"
#include "engine/pyramid.hpp"
#include "common/rng.hpp"
#include "tsvq/search_exhaustive.hpp"
#include "analysis/texture_model.hpp"
#include "tsvq/tsvq_search.hpp"
#include "tsvq/tsvq_train.hpp"
#include "test_support.hpp"

using namespace vqtex;

namespace {

struct Fixture {
    std::vector<Image> pyramid;
    NeighborhoodLayout layout;
    ExampleSet set;
};

Fixture level0_examples(const char* name, int levels = 3) {
    const Image img = vqtex_test::load_corpus(name);
    auto pyr = build_pyramid(img, levels, EdgeMode::Mirror);
    NeighborhoodLayout layout(default_shapes(levels)[0], img.channels, 0, levels);
    ExampleSet set = collect_examples(layout, pyr, false);
    return Fixture{std::move(pyr), layout, std::move(set)};
}

std::vector<uint32_t> all_indices(const ExampleSet& s) {
    return choose_training_subset(s.count(), s.count(), 0);
}

}  // namespace

TEST(Tsvq, TreeHasTheRequestedNumberOfLeaves) {
    const Fixture f = level0_examples("grey_noise_64.png");
    for (uint32_t k : {1u, 2u, 17u, 64u, 300u}) {
        TrainParams p;
        p.max_leaves = k;
        const Codebook book = train_codebook(f.set, all_indices(f.set), p);
        EXPECT_EQ(book.leaf_count(), k);
        EXPECT_EQ(book.node_count(), 2 * std::size_t(k) - 1);
        uint64_t weights = 0;
        for (std::size_t l = 0; l < book.leaf_count(); ++l) weights += book.leaf_count_of(l);
        EXPECT_EQ(weights, f.set.count());  // every training vector lands in one leaf
    }
}

TEST(Tsvq, DistortionThresholdStopsGrowth) {
    const Fixture f = level0_examples("grey_noise_64.png");
    TrainParams loose;
    loose.max_leaves = 4096;
    loose.distortion_threshold = 1e9;  // the root already satisfies it
    EXPECT_EQ(train_codebook(f.set, all_indices(f.set), loose).leaf_count(), 1u);
    TrainParams medium = loose;
    medium.distortion_threshold = 2000;
    const std::size_t n = train_codebook(f.set, all_indices(f.set), medium).leaf_count();
    EXPECT_GT(n, 1u);
    EXPECT_LT(n, f.set.count());
}

TEST(Tsvq, TrainingIsDeterministicForAnyThreadCount) {
    const Fixture f = level0_examples("cellular_128.png", 4);
    TrainParams p;
    p.max_leaves = 200;
    p.threads = 1;
    const Codebook one = train_codebook(f.set, all_indices(f.set), p);
    for (int t : {2, 3, 7}) {
        p.threads = t;
        EXPECT_TRUE(train_codebook(f.set, all_indices(f.set), p) == one) << t << " threads";
    }
}

TEST(Tsvq, MedoidLeavesAreRealExampleNeighbourhoods) {
    const Fixture f = level0_examples("weave_128.png");
    TrainParams p;
    p.max_leaves = 50;
    const Codebook book = train_codebook(f.set, all_indices(f.set), p);
    for (std::size_t l = 0; l < book.leaf_count(); ++l) {
        const uint32_t key = book.leaf_key(l);
        ASSERT_LT(key, f.set.count());
        EXPECT_TRUE(std::equal(f.set.vector(key), f.set.vector(key) + f.set.stride, book.leaf_codeword(l)));
        EXPECT_TRUE(std::equal(f.set.pixel(key), f.set.pixel(key) + 3, book.leaf_pixel(l)));
    }
}

TEST(Tsvq, InternalCodewordsAreDerivedFromTheLeaves) {
    // The decoder rebuilds the search structure from leaves and topology
    // alone: finalize() on a copy with scrambled internal codewords restores them.
    const Fixture f = level0_examples("weave_128.png");
    TrainParams p;
    p.max_leaves = 40;
    const Codebook book = train_codebook(f.set, all_indices(f.set), p);
    Codebook copy = book;
    for (std::size_t n = 0; n < copy.node_count(); ++n)
        if (copy.node(n).first_child >= 0) copy.codeword(n)[0] ^= 0x5A;
    copy.finalize();
    EXPECT_TRUE(copy == book);
}

TEST(Tsvq, FullBacktrackingEqualsExhaustiveSearchOverTheCodebook) {
    const Fixture f = level0_examples("clouds_128.png", 4);
    TrainParams p;
    p.max_leaves = 256;
    auto book = std::make_shared<const Codebook>(train_codebook(f.set, all_indices(f.set), p));
    const TsvqMatcher matcher(book, uint32_t(book->leaf_count()));
    auto scratch = matcher.make_scratch();
    for (std::size_t i = 0; i < f.set.count(); i += 7) {
        const uint8_t* q = f.set.vector(i);
        EXPECT_EQ(matcher.search(q, uint32_t(book->leaf_count()), scratch.get()),
                  matcher.nearest_leaf_exhaustive(q));
    }
}

TEST(Tsvq, MoreBacktrackingNeverFindsAWorseLeaf) {
    const Fixture f = level0_examples("cellular_128.png", 4);
    TrainParams p;
    p.max_leaves = 300;
    auto book = std::make_shared<const Codebook>(train_codebook(f.set, all_indices(f.set), p));
    const TsvqMatcher matcher(book, 1);
    const dsp::Kernels& k = dsp::kernels();
    std::size_t improved = 0;
    for (std::size_t i = 0; i < f.set.count(); i += 11) {
        const uint8_t* q = f.set.vector(i);
        uint32_t previous = UINT32_MAX;
        for (uint32_t L : {1u, 2u, 4u, 16u, 300u}) {
            const uint32_t d = k.ssd(q, book->leaf_codeword(matcher.search(q, L, nullptr)), book->stride());
            EXPECT_LE(d, previous);
            if (d < previous && previous != UINT32_MAX) ++improved;
            previous = d;
        }
    }
    EXPECT_GT(improved, 0u);  // backtracking does something
}

TEST(Tsvq, OneLeafPerTrainingVectorIsPossibleEvenWithDuplicates) {
    // The checkerboard has many identical neighbourhoods: Lloyd cannot split
    // them, the trainer must still reach one leaf per vector.
    const Fixture f = level0_examples("checks_p16_64.png");
    TrainParams p;
    p.max_leaves = uint32_t(f.set.count());
    const Codebook book = train_codebook(f.set, all_indices(f.set), p);
    ASSERT_EQ(book.leaf_count(), f.set.count());
    std::set<uint32_t> keys;
    for (std::size_t l = 0; l < book.leaf_count(); ++l) keys.insert(book.leaf_key(l));
    EXPECT_EQ(keys.size(), f.set.count());
}

TEST(Tsvq, FullCodebookWithFullBacktrackingSynthesisesExactlyLikeExhaustive) {
    for (const char* name : {"checks_p16_64.png", "grey_noise_64.png", "leaves_rgba_64.png"}) {
        const Image ex = vqtex_test::load_corpus(name);
        vqtex_synth_params p = vqtex_test::default_params(48, 40, 21);
        p.paper.search = VQTEX_SEARCH_EXHAUSTIVE;
        const Image exhaustive = vqtex_test::synthesize(ex, p);
        p.paper.search = VQTEX_SEARCH_TSVQ;
        p.paper.tsvq.codeword_fraction = 1.0f;
        p.paper.backtrack = 1u << 30;  // visit every leaf
        const Image tsvq = vqtex_test::synthesize(ex, p);
        EXPECT_EQ(tsvq, exhaustive) << name;
    }
}

TEST(Tsvq, TrainingSubsetIsDeterministicAndSized) {
    const auto a = choose_training_subset(1000, 100, 5);
    const auto b = choose_training_subset(1000, 100, 5);
    const auto c = choose_training_subset(1000, 100, 6);
    EXPECT_EQ(a, b);
    EXPECT_NE(a, c);
    EXPECT_EQ(a.size(), 100u);
    EXPECT_TRUE(std::is_sorted(a.begin(), a.end()));
    EXPECT_EQ(std::set<uint32_t>(a.begin(), a.end()).size(), 100u);
}

TEST(Tsvq, TrainFractionLimitsTheTrainingSet) {
    const Image ex = vqtex_test::load_corpus("cellular_128.png");
    ModelParams mp;
    mp.train_fraction = 0.1f;
    mp.codeword_fraction = 1.0f;
    const AnalysisResult a = analyse_example(ex, mp, VQTEX_SEARCH_TSVQ, 1, 1, nullptr);
    // With all leaves kept, leaves = training vectors used = 10% of the level.
    EXPECT_NEAR(double(a.codebooks[0]->leaf_count()), 0.1 * double(a.training_vectors[0]), 1.0);
}

TEST(Tsvq, NearTieChoiceIsTheSameForTsvqAndExhaustive) {
    // With a tolerance, the winner among near-ties depends only on the set of
    // qualifying candidates and the per-pixel salt, not on the search order:
    // a full codebook searched fully picks exactly what exhaustive search picks.
    const Image ex = vqtex_test::load_corpus("grey_noise_64.png");
    vqtex_synth_params p = vqtex_test::default_params(40, 40, 5);
    p.paper.tolerance = 64;
    p.paper.search = VQTEX_SEARCH_EXHAUSTIVE;
    const Image exhaustive = vqtex_test::synthesize(ex, p);
    p.paper.search = VQTEX_SEARCH_TSVQ;
    p.paper.tsvq.codeword_fraction = 1.0f;
    p.paper.backtrack = 1u << 30;
    EXPECT_EQ(vqtex_test::synthesize(ex, p), exhaustive);
    p.paper.tolerance = 0;
    EXPECT_NE(vqtex_test::synthesize(ex, p), exhaustive);  // the tolerance does something
}

TEST(Tsvq, EntriesKeepRareContinuationsAlive) {
    // With a small codebook, one output per leaf collapses the texture into
    // its commonest patterns; several entries per leaf keep the variety of
    // the example. Measured as the number of distinct output colours.
    const Image ex = vqtex_test::load_corpus("cellular_128.png");
    auto distinct = [](const Image& img) {
        std::set<uint32_t> colours;
        for (std::size_t i = 0; i < img.pixel_count(); ++i)
            colours.insert(uint32_t(img.pixels[i * 3]) << 16 | uint32_t(img.pixels[i * 3 + 1]) << 8 |
                           img.pixels[i * 3 + 2]);
        return colours.size();
    };
    vqtex_synth_params p = vqtex_test::default_params(128, 128, 3);
    p.paper.tsvq.codeword_fraction = 0.03f;
    p.paper.tsvq.entries_per_leaf = 1;
    const std::size_t one = distinct(vqtex_test::synthesize(ex, p));
    p.paper.tsvq.entries_per_leaf = 16;
    const Image many = vqtex_test::synthesize(ex, p);
    EXPECT_GT(distinct(many), 2 * one);
    // Entries are real example pixels: every output colour exists in the example.
    const std::size_t in_example = distinct(ex);
    std::set<uint32_t> ex_colours;
    for (std::size_t i = 0; i < ex.pixel_count(); ++i)
        ex_colours.insert(uint32_t(ex.pixels[i * 3]) << 16 | uint32_t(ex.pixels[i * 3 + 1]) << 8 | ex.pixels[i * 3 + 2]);
    for (std::size_t i = 0; i < many.pixel_count(); ++i)
        EXPECT_TRUE(ex_colours.count(uint32_t(many.pixels[i * 3]) << 16 | uint32_t(many.pixels[i * 3 + 1]) << 8 |
                                     many.pixels[i * 3 + 2]));
    EXPECT_GT(in_example, 0u);
}

TEST(Tsvq, OneLeafSearchEqualsDistanceDescent) {
    // Visiting one leaf must take exactly the branch the two distances
    // would at every node (ties to the first child).
    const Fixture f = level0_examples("cellular_128.png", 4);
    TrainParams p;
    p.max_leaves = 500;
    auto book = std::make_shared<const Codebook>(train_codebook(f.set, all_indices(f.set), p));
    const TsvqMatcher matcher(book, 1);
    const dsp::Kernels& k = dsp::kernels();
    for (std::size_t i = 0; i < f.set.count(); i += 5) {
        const uint8_t* q = f.set.vector(i);
        std::size_t node = 0;
        while (book->node(node).first_child >= 0) {
            const std::size_t a = std::size_t(book->node(node).first_child);
            node = k.ssd(q, book->codeword(a), book->stride()) <= k.ssd(q, book->codeword(a + 1), book->stride())
                       ? a
                       : a + 1;
        }
        EXPECT_EQ(matcher.search(q, 1, nullptr), std::size_t(book->node(node).leaf));
    }
}

TEST(Tsvq, TwoLeafSearchVisitsTheNearestPassedBranchSecond) {
    // L = 2, the decoder's default, has its own short path in search: one
    // walk, then one from the nearest branch it passed (by distance, then
    // node), and the nearer leaf (by distance, then key). The reference here
    // is that definition with plain distances. The periodic texture has
    // leaves with equal codewords, so that ties between the two leaves occur.
    std::size_t second_won = 0, ties = 0;
    for (const char* name : {"cellular_128.png", "checks_p16_64.png"}) {
        SCOPED_TRACE(name);
        const Fixture f = level0_examples(name, 4);
        TrainParams p;
        p.max_leaves = 400;
        auto book = std::make_shared<const Codebook>(train_codebook(f.set, all_indices(f.set), p));
        const TsvqMatcher matcher(book, 2);
        auto scratch = matcher.make_scratch();
        const dsp::Kernels& k = dsp::kernels();
        const std::size_t n = book->stride();
        auto walk = [&](const uint8_t* q, std::size_t node, std::vector<std::pair<uint32_t, std::size_t>>* passed) {
            while (book->node(node).first_child >= 0) {
                const std::size_t a = std::size_t(book->node(node).first_child);
                const uint32_t d0 = k.ssd(q, book->codeword(a), n), d1 = k.ssd(q, book->codeword(a + 1), n);
                if (passed) passed->emplace_back(d0 <= d1 ? d1 : d0, d0 <= d1 ? a + 1 : a);
                node = d0 <= d1 ? a : a + 1;
            }
            return node;
        };
        for (std::size_t i = 0; i < f.set.count(); i += 3) {
            const uint8_t* q = f.set.vector(i);
            std::vector<std::pair<uint32_t, std::size_t>> passed;
            const std::size_t first = walk(q, 0, &passed);
            const std::size_t second = walk(q, std::min_element(passed.begin(), passed.end())->second, nullptr);
            const uint32_t d1 = k.ssd(q, book->codeword(first), n), d2 = k.ssd(q, book->codeword(second), n);
            const std::size_t leaf1 = std::size_t(book->node(first).leaf), leaf2 = std::size_t(book->node(second).leaf);
            const bool take_second = d2 < d1 || (d2 == d1 && book->leaf_key(leaf2) < book->leaf_key(leaf1));
            second_won += take_second;
            ties += d1 == d2 && leaf1 != leaf2;
            ASSERT_EQ(matcher.search(q, 2, scratch.get()), take_second ? leaf2 : leaf1) << "vector " << i;
        }
    }
    EXPECT_GT(second_won, 0u);  // the second walk matters
    EXPECT_GT(ties, 0u);        // and ties between the two leaves are covered
}

TEST(Tsvq, KeylessEntryChoiceIsTheLowestRankedEntry) {
    // Without keys every entry of a leaf qualifies, and the pixel's salt
    // alone chooses: the entry i < n with the lowest rank_hash(salt ^
    // kEntrySalt, i). The matcher answers from a running minimum made before
    // the search; the reference is the definition.
    const Fixture f = level0_examples("cellular_128.png", 4);
    TrainParams p;
    p.max_leaves = 3000;  // small leaves too, with fewer members than entries
    p.entries_per_leaf = 12;
    auto book = std::make_shared<const Codebook>(train_codebook(f.set, all_indices(f.set), p));
    ASSERT_TRUE(book->key_offsets().empty());
    const TsvqMatcher matcher(book, 2);
    Rng rng(5);
    std::set<std::size_t> counts, chosen;
    for (int trial = 0; trial < 40; ++trial) {
        const uint64_t salt = rng.next();
        TsvqMatcher::EntryRanking ranking;
        matcher.rank_entries(salt, ranking);
        for (std::size_t leaf = 0; leaf < book->leaf_count(); ++leaf) {
            const std::size_t n = std::min(book->entry_count(leaf), TsvqMatcher::kMaxEntries);
            std::size_t expected = 0;
            for (std::size_t i = 1; i < n; ++i)
                if (dsp::rank_hash(salt ^ TsvqMatcher::kEntrySalt, uint32_t(i)) <
                    dsp::rank_hash(salt ^ TsvqMatcher::kEntrySalt, uint32_t(expected)))
                    expected = i;
            ASSERT_EQ(matcher.choose_entry(leaf, f.set.vector(0), ranking), expected) << "leaf " << leaf;
            counts.insert(n);
            chosen.insert(expected);
        }
    }
    EXPECT_GT(counts.size(), 2u);   // leaves of several sizes
    EXPECT_GT(chosen.size(), 8u);   // and many different winners
}

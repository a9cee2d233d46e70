// tsvq_train.cpp - TSVQ training by recursive generalised-Lloyd splits
// (paper section 4).
//
// The tree grows greedily: every leaf carries a tentative split, and the leaf
// whose split lowers the total distortion most is split first, until the tree
// has K leaves, the mean distortion falls below the threshold or nothing can
// be split. A split starts its two children at the centroid and at a
// perturbed centroid (halfway towards the member farthest from it) and runs
// Lloyd iterations until the partition is stable.
//
// All arithmetic is integer: centroids are rounded means of exact 64-bit sums,
// distances exact SSD, ties broken by index. Chunked sums do not depend on the
// chunking, so the tree is the same for any thread count.
//
// Leaf representative. With centroids, each leaf's output pixel is an average
// of many example pixels: the synthesised texture loses contrast and fine
// detail (the blur the paper warns about, section 4). The medoid is a real
// example neighbourhood with its real centre pixel, so outputs keep the
// example's sharpness and colours. Measured on 10 shared-corpus textures
// (128x128 exemplar crops, outputs scored against held-out crops, see
// docs/RATE.md): with 1/8 of the vectors as leaves, medoids give a sliced
// Wasserstein distance of 12.9 against 16.5 for centroids and a mean
// gradient of 11.1 against 5.2 (held-out: 15.4); with 3%, 14.1 against 15.6
// and 9.6 against 4.8. (With one leaf per vector the two are the same.)
// Medoid is the default.
#include "tsvq/tsvq_train.hpp"

#include <algorithm>
#include <cstring>
#include <numeric>
#include <queue>

#include "dsp/dsp.hpp"
#include "common/error.hpp"
#include "engine/matcher.hpp"
#include "common/parallel.hpp"
#include "common/rng.hpp"

namespace vqtex {

std::vector<uint32_t> choose_training_subset(std::size_t total, std::size_t count, uint64_t seed) {
    std::vector<uint32_t> all(total);
    std::iota(all.begin(), all.end(), 0u);
    if (count >= total) return all;
    Rng rng = Rng::stream(seed, 0x747261696Eull /* "train" */);
    for (std::size_t i = 0; i < count; ++i)
        std::swap(all[i], all[i + std::size_t(rng.below(total - i))]);
    all.resize(count);
    std::sort(all.begin(), all.end());
    return all;
}

namespace {

constexpr std::size_t kGrain = 2048;

struct Cluster {
    std::vector<uint32_t> members;  // example indices, ascending
    std::vector<uint64_t> sum;      // per dimension, exact
    std::vector<uint8_t> centroid;  // stride bytes
    uint64_t distortion = 0;        // sum of SSD to the centroid
    uint32_t far_distance = 0;      // largest SSD to the centroid
    std::size_t far = 0;            // position in members of the (first) farthest
};

struct Split {
    bool possible = false;
    uint64_t gain = 0;
    Cluster a, b;
};

class Trainer {
public:
    Trainer(const ExampleSet& ex, const TrainParams& p) : ex_(ex), p_(p), k_(dsp::kernels()) {}

    uint32_t ssd(const uint8_t* a, const uint8_t* b) const { return k_.ssd(a, b, ex_.stride); }

    // __restrict: bytes may alias anything, so without it the compiler must
    // reload the vector after every store and cannot vectorise.
    void add(std::vector<uint64_t>& sum, uint32_t member) const {
        const uint8_t* __restrict v = ex_.vector(member);
        uint64_t* __restrict s = sum.data();
        for (std::size_t d = 0; d < ex_.dimension; ++d) s[d] += v[d];
    }
    void subtract(std::vector<uint64_t>& sum, uint32_t member) const {
        const uint8_t* __restrict v = ex_.vector(member);
        uint64_t* __restrict s = sum.data();
        for (std::size_t d = 0; d < ex_.dimension; ++d) s[d] -= v[d];
    }

    std::vector<uint8_t> mean(const std::vector<uint64_t>& sum, uint64_t n) const {
        std::vector<uint8_t> m(ex_.stride, 0);
        for (std::size_t d = 0; d < ex_.dimension; ++d) m[d] = uint8_t((sum[d] + n / 2) / n);
        return m;
    }

    // Sum and centroid from the members.
    void summarise(Cluster& c) const {
        c.sum.assign(ex_.dimension, 0);
        for (uint32_t m : c.members) add(c.sum, m);
        c.centroid = mean(c.sum, c.members.size());
    }

    // Distortion, and the member farthest from the centroid (lowest index
    // on ties), which a split starts from.
    void compute_distortion(Cluster& c) const {
        const std::size_t chunks = (c.members.size() + kGrain - 1) / kGrain;
        struct Partial {
            uint64_t sum = 0;
            uint32_t far_distance = 0;
            std::size_t far = 0;
        };
        std::vector<Partial> partial(chunks);
        parallel_for(threads_for(c.members.size()), c.members.size(), kGrain,
                     [&](std::size_t b, std::size_t e) {
                         Partial p{0, 0, b};
                         for (std::size_t i = b; i < e; ++i) {
                             const uint32_t d = ssd(ex_.vector(c.members[i]), c.centroid.data());
                             p.sum += d;
                             if (d > p.far_distance) p.far_distance = d, p.far = i;
                         }
                         partial[b / kGrain] = p;
                     });
        c.distortion = 0;
        c.far_distance = 0;
        c.far = 0;
        for (const Partial& p : partial) {
            c.distortion += p.sum;
            if (p.far_distance > c.far_distance) c.far_distance = p.far_distance, c.far = p.far;
        }
    }

    // Assign members to the nearer of two codewords (ties to the first):
    // per-member flags, 1 = second. |v-b|^2 < |v-a|^2 exactly when
    // 2 v.(a-b) < |a|^2 - |b|^2: one dot product per member instead of two
    // distances, the same partition.
    void assign(const Cluster& c, const uint8_t* ca, const uint8_t* cb, std::vector<uint8_t>& side) const {
        side.resize(c.members.size());
        std::vector<int16_t> normal(ex_.stride, 0);
        int64_t offset = 0;
        for (std::size_t d = 0; d < ex_.stride; ++d) {
            normal[d] = int16_t(int(ca[d]) - int(cb[d]));
            offset += int64_t(ca[d]) * ca[d] - int64_t(cb[d]) * cb[d];
        }
        parallel_for(threads_for(c.members.size()), c.members.size(), kGrain,
                     [&](std::size_t b, std::size_t e) {
                         for (std::size_t i = b; i < e; ++i) {
                             const int64_t dot = k_.dot(ex_.vector(c.members[i]), normal.data(), ex_.stride);
                             side[i] = 2 * dot < offset ? 1 : 0;
                         }
                     });
    }

    Split try_split(const Cluster& c) const {
        Split s;
        const std::size_t n = c.members.size();
        if (n < 2) return s;
        s.possible = true;
        const uint32_t far_distance = c.far_distance;
        const std::size_t far = c.far;
        std::vector<uint8_t> side;
        bool lloyd_ok = far_distance > 0;
        if (lloyd_ok) {
            std::vector<uint8_t> ca = c.centroid, cb = c.centroid;
            const uint8_t* f = ex_.vector(c.members[far]);
            for (std::size_t d = 0; d < ex_.dimension; ++d)
                cb[d] = uint8_t(int(ca[d]) + (int(f[d]) - int(ca[d])) / 2);
            if (cb == ca) std::memcpy(cb.data(), f, ex_.dimension);
            // Lloyd iterations with sums updated only for the members that
            // change sides, so later iterations cost little beyond the
            // distances. The sums are exact, so this is the same partition
            // plain recomputation gives.
            std::vector<uint8_t> next;
            std::vector<uint64_t> sum_b(ex_.dimension, 0);
            std::size_t count_b = 0;
            side.assign(n, 0);
            for (int it = 0; it < p_.max_lloyd_iterations; ++it) {
                assign(c, ca.data(), cb.data(), next);
                if (it > 0 && next == side) break;
                for (std::size_t i = 0; i < n; ++i) {
                    if (next[i] == side[i]) continue;
                    if (next[i]) add(sum_b, c.members[i]), ++count_b;
                    else subtract(sum_b, c.members[i]), --count_b;
                }
                side.swap(next);
                if (count_b == 0 || count_b == n) {
                    lloyd_ok = false;
                    break;
                }
                std::vector<uint64_t> sum_a = c.sum;
                for (std::size_t d = 0; d < ex_.dimension; ++d) sum_a[d] -= sum_b[d];
                ca = mean(sum_a, n - count_b);
                cb = mean(sum_b, count_b);
            }
        }
        if (lloyd_ok) {
            for (std::size_t i = 0; i < n; ++i) (side[i] ? s.b : s.a).members.push_back(c.members[i]);
        } else {
            // Identical vectors (or a degenerate start): split by position so
            // that a codebook of one leaf per vector is always reachable.
            const std::size_t half = n / 2;
            s.a.members.assign(c.members.begin(), c.members.begin() + std::ptrdiff_t(half));
            s.b.members.assign(c.members.begin() + std::ptrdiff_t(half), c.members.end());
        }
        // The smaller side is summed; the larger is the parent minus it.
        Cluster& small = s.a.members.size() <= s.b.members.size() ? s.a : s.b;
        Cluster& large = &small == &s.a ? s.b : s.a;
        summarise(small);
        large.sum = c.sum;
        for (std::size_t d = 0; d < ex_.dimension; ++d) large.sum[d] -= small.sum[d];
        large.centroid = mean(large.sum, large.members.size());
        compute_distortion(s.a);
        compute_distortion(s.b);
        const uint64_t after = s.a.distortion + s.b.distortion;
        s.gain = c.distortion > after ? c.distortion - after : 0;
        return s;
    }

    void set_leaf(Codebook& book, std::size_t node, const Cluster& c) const {
        const int ch = ex_.channels;
        const std::size_t entry_size = book.entry_size();
        std::vector<uint8_t> entries;
        auto add_entry = [&](uint32_t member, const uint8_t* pixel) {
            entries.insert(entries.end(), pixel, pixel + ch);
            for (uint16_t o : book.key_offsets()) entries.push_back(ex_.vector(member)[o]);
        };
        uint32_t representative;
        if (p_.representative == LeafRepresentative::Medoid) {
            uint32_t best = UINT32_MAX;
            representative = c.members.front();
            for (uint32_t m : c.members) {
                const uint32_t d = ssd(ex_.vector(m), c.centroid.data());
                if (d < best) best = d, representative = m;
            }
            add_entry(representative, ex_.pixel(representative));
        } else {
            uint64_t sum[kMaxChannels] = {};
            for (uint32_t m : c.members)
                for (int k = 0; k < ch; ++k) sum[k] += ex_.pixel(m)[k];
            uint8_t pixel[kMaxChannels] = {};
            const uint64_t n = c.members.size();
            for (int k = 0; k < ch; ++k) pixel[k] = uint8_t((sum[k] + n / 2) / n);
            representative = c.members.front();
            // The centroid's own key: its codeword at the key taps.
            entries.insert(entries.end(), pixel, pixel + ch);
            for (uint16_t o : book.key_offsets()) entries.push_back(c.centroid[o]);
        }
        if (p_.entries_per_leaf > 1 && c.members.size() > 1) {
            // A fixed pseudo-random sample of the other members: an unbiased
            // sample of what follows this context in the example.
            std::vector<uint32_t> others;
            for (uint32_t m : c.members)
                if (m != representative) others.push_back(m);
            std::sort(others.begin(), others.end(), [](uint32_t a, uint32_t b) {
                return candidate_rank(0x656E74726965ull /* "entrie" */, a) <
                       candidate_rank(0x656E74726965ull, b);
            });
            const std::size_t extra = std::min<std::size_t>(others.size(), p_.entries_per_leaf - 1);
            for (std::size_t i = 0; i < extra; ++i) add_entry(others[i], ex_.pixel(others[i]));
        }
        if (book.key_length() == 0 && entries.size() > entry_size) {
            // Keyless entries are interchangeable (the salt picks one at
            // random), so keep them sorted: the file codes each as a small
            // difference from the previous one.
            std::vector<std::vector<uint8_t>> sorted;
            for (std::size_t i = 0; i < entries.size(); i += entry_size)
                sorted.emplace_back(entries.begin() + std::ptrdiff_t(i), entries.begin() + std::ptrdiff_t(i + entry_size));
            std::sort(sorted.begin(), sorted.end(), [](const auto& a, const auto& b) {
                int sa = 0, sb = 0;
                for (std::size_t k = 0; k < a.size(); ++k) sa += a[k], sb += b[k];
                return sa != sb ? sa < sb : a < b;
            });
            entries.clear();
            for (const auto& e : sorted) entries.insert(entries.end(), e.begin(), e.end());
        }
        const uint8_t* cw = p_.representative == LeafRepresentative::Medoid ? ex_.vector(representative)
                                                                            : c.centroid.data();
        book.set_leaf(node, cw, uint32_t(c.members.size()), representative, entries.data(),
                      entries.size() / entry_size);
    }

    int threads_for(std::size_t n) const { return n >= 2 * kGrain ? p_.threads : 1; }

private:
    const ExampleSet& ex_;
    const TrainParams& p_;
    const dsp::Kernels& k_;
};

}  // namespace

Codebook train_codebook(const ExampleSet& examples, const std::vector<uint32_t>& subset,
                        const TrainParams& params) {
    if (subset.empty()) fail(VQTEX_ERROR_IMAGE_TOO_SMALL, "no example neighbourhood to train on");
    if (params.max_leaves < 1) fail(VQTEX_ERROR_INVALID_ARGUMENT, "a codebook needs at least one codeword");
    Trainer trainer(examples, params);
    Codebook book(examples.dimension, examples.stride, examples.channels,
                  params.entries_per_leaf > 1 || params.keys_on_single_entries ? params.key_offsets : std::vector<uint16_t>{});
    // Without keys several entries are still useful: chosen at random.
    book.add_root();

    // Per node: its cluster and its tentative split, while it is a leaf.
    std::vector<Cluster> clusters(1);
    std::vector<Split> splits(1);
    std::vector<int> depth(1, 0);
    clusters[0].members = subset;
    trainer.summarise(clusters[0]);
    trainer.compute_distortion(clusters[0]);
    uint64_t total = clusters[0].distortion;
    splits[0] = trainer.try_split(clusters[0]);

    // Max-heap on gain; among equal gains the oldest node first.
    using Entry = std::pair<uint64_t, int64_t>;  // gain, -node
    std::priority_queue<Entry> heap;
    if (splits[0].possible) heap.push({splits[0].gain, 0});
    std::size_t leaves = 1;
    const double n = double(subset.size());
    while (leaves < params.max_leaves && !heap.empty()) {
        if (params.distortion_threshold > 0 && double(total) / n <= params.distortion_threshold) break;
        const std::size_t node = std::size_t(-heap.top().second);
        heap.pop();
        Split split = std::move(splits[node]);
        const std::size_t first = book.split(node);
        clusters.resize(first + 2);
        splits.resize(first + 2);
        depth.resize(first + 2, depth[node] + 1);
        clusters[first] = std::move(split.a);
        clusters[first + 1] = std::move(split.b);
        clusters[node] = Cluster{};
        total -= split.gain;
        ++leaves;
        for (std::size_t child = first; child < first + 2; ++child) {
            if (depth[child] >= kMaxTreeDepth) continue;  // the format's limit
            splits[child] = trainer.try_split(clusters[child]);
            if (splits[child].possible) heap.push({splits[child].gain, -int64_t(child)});
        }
    }
    for (std::size_t node = 0; node < book.node_count(); ++node)
        if (book.node(node).first_child < 0) trainer.set_leaf(book, node, clusters[node]);
    book.finalize();
    return book;
}

}  // namespace vqtex

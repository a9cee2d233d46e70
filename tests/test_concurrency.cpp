// test_concurrency.cpp - several encodes, decodes, inspections and
// syntheses at once in one process, on different data and on shared data,
// each with its own thread count: every one gives exactly the bytes it gives
// alone, and cancelling one leaves the others untouched. scripts/
// test-sanitizers.sh runs this suite under ThreadSanitizer, which also
// reports any data race between the calls.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <stdexcept>
#include <thread>
#include <vector>

#include "codec_support.hpp"
#include "common/parallel.hpp"
#include "engine/wavefront.hpp"
#include "test_support.hpp"

using namespace vqtex_test;

namespace {

// Small examples of 1 to 4 channels, loaded before any thread starts.
vqtex::Image crop(const vqtex::Image& src, int side, int channels) {
    vqtex::Image out(side, side, channels);
    for (int y = 0; y < side; ++y)
        for (int x = 0; x < side; ++x)
            for (int c = 0; c < channels; ++c) out.at(x, y)[c] = src.at(x, y)[c % src.channels];
    return out;
}

const std::vector<vqtex::Image>& examples() {
    static const std::vector<vqtex::Image> images = {
        crop(load_corpus("grey_noise_64.png"), 40, 1),
        crop(load_corpus("leaves_rgba_64.png"), 40, 4),
        crop(load_corpus("weave_128.png"), 40, 3),
        crop(load_corpus("cellular_128.png"), 40, 2),
    };
    return images;
}

struct Results {
    std::vector<uint8_t> file;
    vqtex::Image decoded;
    std::vector<vqtex::Image> mips;
    uint32_t inspected_codewords = 0;
    vqtex::Image synthesised;
    // The default path: an atlas file (libaom, dav1d, the coherent engine)
    // and the coherent engine on the example itself.
    std::vector<uint8_t> atlas_file;
    vqtex::Image atlas_decoded;
    vqtex::Image coherent;
};

vqtex::Image from_c(vqtex_image& img) {
    vqtex::Image out(int(img.width), int(img.height), int(img.channels));
    std::memcpy(out.pixels.data(), img.pixels, out.byte_count());
    vqtex_image_free(&img);
    return out;
}

// The whole public pipeline on one example with `threads` inner threads.
Results run_all(const vqtex::Image& example, uint32_t threads) {
    Results r;
    vqtex_encode_params ep = fast_encode_params();
    ep.threads = threads;
    r.file = encode(example, ep);
    r.decoded = decode(r.file, decode_params(56, 36, 11, threads));

    vqtex_decode_params dp = decode_params(20, 12, 5, threads);
    vqtex_image levels[8];
    uint32_t count = 0;
    if (vqtex_decode_mips(&dp, r.file.data(), r.file.size(), levels, 8, &count, nullptr) != VQTEX_OK)
        throw std::runtime_error("decode_mips failed");
    for (uint32_t i = 0; i < count; ++i) r.mips.push_back(from_c(levels[i]));

    vqtex_file_info info{};
    if (vqtex_inspect(r.file.data(), r.file.size(), 0, &info, nullptr) != VQTEX_OK)
        throw std::runtime_error("inspect failed");
    r.inspected_codewords = info.codewords[0];

    vqtex_synth_params sp = default_params(24, 24, 3);
    sp.threads = threads;
    sp.levels = 2;
    sp.paper.tsvq.codeword_fraction = 0.25f;
    r.synthesised = synthesize(example, sp);

    vqtex_encode_params ap;
    vqtex_encode_params_init(&ap);  // an atlas, the default
    ap.threads = threads;
    r.atlas_file = encode(example, ap);
    r.atlas_decoded = decode(r.atlas_file, decode_params(52, 44, 7, threads));

    vqtex_synth_params cp;
    vqtex_synth_params_init(&cp);  // the coherent engine, the default
    cp.width = 60;
    cp.height = 48;
    cp.seed = 4;
    cp.threads = threads;
    r.coherent = synthesize(example, cp);
    return r;
}

void expect_same(const Results& got, const Results& want, const std::string& what) {
    EXPECT_EQ(got.file, want.file) << what;
    EXPECT_EQ(got.decoded, want.decoded) << what;
    EXPECT_EQ(got.mips, want.mips) << what;
    EXPECT_EQ(got.inspected_codewords, want.inspected_codewords) << what;
    EXPECT_EQ(got.synthesised, want.synthesised) << what;
    EXPECT_EQ(got.atlas_file, want.atlas_file) << what;
    EXPECT_EQ(got.atlas_decoded, want.atlas_decoded) << what;
    EXPECT_EQ(got.coherent, want.coherent) << what;
}

}  // namespace

TEST(Concurrency, EverythingAtOnceGivesTheSameBytesAsOneAtATime) {
    const auto& ex = examples();
    std::vector<Results> alone;
    for (const auto& e : ex) alone.push_back(run_all(e, 1));
    // Two calls per example, with 1, 2 or 3 inner threads each, all at once.
    const std::size_t jobs = 2 * ex.size();
    std::vector<Results> together(jobs);
    std::vector<std::string> errors(jobs);
    std::vector<std::thread> pool;
    for (std::size_t j = 0; j < jobs; ++j)
        pool.emplace_back([&, j] {
            try {
                together[j] = run_all(ex[j % ex.size()], uint32_t(1 + j % 3));
            } catch (const std::exception& e) {
                errors[j] = e.what();
            }
        });
    for (auto& t : pool) t.join();
    for (std::size_t j = 0; j < jobs; ++j) {
        ASSERT_EQ(errors[j], "") << "job " << j;
        expect_same(together[j], alone[j % ex.size()], "job " + std::to_string(j));
    }
}

TEST(Concurrency, ManyDecodesOfOneSharedBuffer) {
    const std::vector<uint8_t> file = encode(examples()[2], fast_encode_params());
    const vqtex::Image want = decode(file, decode_params(64, 64, 9, 1));
    std::vector<vqtex::Image> got(6);
    std::vector<std::thread> pool;
    for (std::size_t j = 0; j < got.size(); ++j)
        pool.emplace_back([&, j] { got[j] = decode(file, decode_params(64, 64, 9, uint32_t(1 + j % 2))); });
    for (auto& t : pool) t.join();
    for (std::size_t j = 0; j < got.size(); ++j) EXPECT_EQ(got[j], want) << "decode " << j;
}

TEST(Concurrency, CancellingOneCallLeavesTheOthersUntouched) {
    const auto& ex = examples();
    const std::vector<uint8_t> file = encode(ex[0], fast_encode_params());
    const vqtex::Image want = decode(file, decode_params(48, 48, 4, 2));
    std::atomic<int> calls{0};
    auto cancel = [](void* user, vqtex_stage, uint64_t, uint64_t) -> int {
        static_cast<std::atomic<int>*>(user)->fetch_add(1);
        return 0;
    };
    std::vector<vqtex::Image> got(3);
    vqtex_status cancelled_status = VQTEX_OK;
    std::vector<std::thread> pool;
    pool.emplace_back([&] {
        vqtex_decode_params p = decode_params(48, 48, 4, 2);
        p.progress = cancel;
        p.progress_user = &calls;
        vqtex_image out{};
        cancelled_status = vqtex_decode(&p, file.data(), file.size(), &out, nullptr);
        vqtex_image_free(&out);
    });
    for (std::size_t j = 0; j < got.size(); ++j)
        pool.emplace_back([&, j] { got[j] = decode(file, decode_params(48, 48, 4, 2)); });
    for (auto& t : pool) t.join();
    EXPECT_EQ(cancelled_status, VQTEX_ERROR_CANCELLED);
    EXPECT_GE(calls.load(), 1);
    for (std::size_t j = 0; j < got.size(); ++j) EXPECT_EQ(got[j], want) << "decode " << j;
}

// parallel_for keeps its threads between calls and hands them to one loop
// at a time: loops started from several threads at once, and loops inside
// loops, must still run every item exactly once.
TEST(Concurrency, LoopsFromManyThreadsAndInsideLoopsRunEveryItemOnce) {
    constexpr std::size_t kItems = 3000, kInner = 40;
    std::vector<std::atomic<int>> visits(4 * kItems * kInner);
    std::vector<std::thread> callers;
    for (int caller = 0; caller < 4; ++caller)
        callers.emplace_back([&visits, caller] {
            vqtex::parallel_for(3, kItems, 7, [&](std::size_t b, std::size_t e) {
                for (std::size_t i = b; i < e; ++i)
                    vqtex::parallel_for(2, kInner, 3, [&](std::size_t ib, std::size_t ie) {
                        for (std::size_t j = ib; j < ie; ++j)
                            visits[(std::size_t(caller) * kItems + i) * kInner + j].fetch_add(1);
                    });
            });
        });
    for (auto& t : callers) t.join();
    for (std::size_t i = 0; i < visits.size(); ++i) ASSERT_EQ(visits[i].load(), 1) << "item " << i;
}

// A process that forks after its loops ran (a benchmark measuring each
// encode in a child, a server's worker processes) has, in the child, the
// kept threads' state but not the threads: the child's loops still run, on
// threads of their own, instead of waiting for ever.
TEST(Concurrency, AChildForkedAfterLoopsRanRunsItsOwnLoops) {
#if defined(__SANITIZE_THREAD__)
    GTEST_SKIP() << "ThreadSanitizer does not let a child forked from a process with threads start threads";
#elif defined(__has_feature)
#if __has_feature(thread_sanitizer)
    GTEST_SKIP() << "ThreadSanitizer does not let a child forked from a process with threads start threads";
#endif
#endif
    std::atomic<int> sum{0};
    vqtex::parallel_for(3, 300, 1, [&](std::size_t b, std::size_t e) {
        for (std::size_t i = b; i < e; ++i) sum.fetch_add(1);
    });
    ASSERT_EQ(sum.load(), 300);
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        ::alarm(60);  // a child that hangs dies of SIGALRM, and the test fails
        std::atomic<int> n{0};
        vqtex::parallel_for(3, 300, 1, [&](std::size_t b, std::size_t e) {
            for (std::size_t i = b; i < e; ++i) n.fetch_add(1);
        });
        ::_exit(n.load() == 300 ? 0 : 1);
    }
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    EXPECT_TRUE(WIFEXITED(status)) << "the child hung or crashed (signal " << (WIFSIGNALED(status) ? WTERMSIG(status) : 0)
                                   << ")";
    EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 0);
}

// An exception thrown inside a loop reaches its caller once every thread is
// done with the loop, and the kept threads serve the next loop as before.
TEST(Concurrency, AnExceptionInALoopReachesItsCallerAndTheThreadsStayUsable) {
    for (int round = 0; round < 3; ++round) {
        EXPECT_THROW(vqtex::parallel_for(2, 64, 1,
                                         [](std::size_t b, std::size_t) {
                                             if (b == 17) throw std::runtime_error("item 17");
                                         }),
                     std::runtime_error);
        std::atomic<std::size_t> sum{0};
        vqtex::parallel_for(2, 1000, 10, [&](std::size_t b, std::size_t e) {
            for (std::size_t i = b; i < e; ++i) sum += i;
        });
        EXPECT_EQ(sum.load(), 999u * 1000u / 2u);
    }
}

// run_together's jobs wait on one another (the synthesis wavefront's rows
// do): every job must be running at the same time, on the kept threads or,
// when they are busy (inside a loop), on threads of the call's own; a
// failing job's exception reaches the caller.
TEST(Concurrency, RunTogetherRunsEveryJobAtOnceAndPassesOnAnException) {
    constexpr int kWorkers = 3;
    const auto meet = [&] {
        std::atomic<int> arrived{0};
        std::atomic<bool> all_met{true};
        vqtex::run_together(kWorkers, [&](int) {
            arrived.fetch_add(1);
            const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
            while (arrived.load() < kWorkers)
                if (std::chrono::steady_clock::now() > deadline) {
                    all_met.store(false);
                    return;
                }
        });
        return all_met.load();
    };
    EXPECT_TRUE(meet());  // on the kept threads
    std::atomic<int> met_inside{0};
    vqtex::parallel_for(2, 2, 1, [&](std::size_t, std::size_t) { met_inside += meet() ? 1 : 0; });
    EXPECT_EQ(met_inside.load(), 2);  // at least one of them on threads of its own
    EXPECT_THROW(vqtex::run_together(kWorkers,
                                     [](int w) {
                                         if (w == 2) throw std::runtime_error("job 2");
                                     }),
                 std::runtime_error);
    EXPECT_TRUE(meet());
}

TEST(Concurrency, RunRowsReleasesTheWaitingRowsWhenOneThrows) {
    // Worker 0's row waits, as a wavefront row waits on the row above, until
    // the scan stops; worker 1's row throws. The failing worker must stop
    // the scan, or worker 0 would wait for ever; the exception then reaches
    // the caller.
    std::atomic<bool> stop{false};
    EXPECT_THROW(vqtex::run_rows(
                     2, 4, stop, [] { return 0; },
                     [&](int index, int, int&) {
                         if (index == 1) throw std::runtime_error("row failed");
                         while (!stop.load()) std::this_thread::yield();
                     }),
                 std::runtime_error);
    EXPECT_TRUE(stop.load());
}

// parallel.cpp - the threads parallel_for and run_together keep between
// calls (see parallel.hpp): a handful of workers that sleep on a condition variable
// and wake for each loop, instead of threads started and joined per loop.
#include "common/parallel.hpp"

#include <chrono>
#include <condition_variable>
#include <exception>
#include <mutex>
#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif
#if defined(__unix__)
#include <unistd.h>
#endif

namespace vqtex::detail {
namespace {

// A loop of the synthesis often follows the last within tens of
// microseconds, less than a sleeping thread takes to wake (a futex round
// trip, longer on a virtual machine). So a thread that is about to sleep,
// or to wait for the others, first polls for a short while.
constexpr auto kSpin = std::chrono::microseconds(100);

template <typename Ready>
bool spin_until(Ready&& ready) {
    // On one core a polling thread only delays the one it waits for.
    static const bool worth_it = std::thread::hardware_concurrency() > 1;
    if (!worth_it) return ready();
    const auto start = std::chrono::steady_clock::now();
    for (int i = 1;; ++i) {
        if (ready()) return true;
#if defined(__x86_64__) || defined(__i386__)
        _mm_pause();
#endif
        if (i % 64 == 0 && std::chrono::steady_clock::now() - start > kSpin) return false;
    }
}

class KeptThreads {
public:
    bool run(int workers, const std::function<void(int)>& job) {
        // More threads than any machine here has cores are not worth keeping.
        constexpr int kMaxKept = 255;
        std::unique_lock<std::mutex> use(in_use_, std::try_to_lock);
        if (!use.owns_lock() || workers - 1 > kMaxKept) return false;
        {
            std::lock_guard<std::mutex> lock(state_);
            while (int(threads_.size()) < workers - 1) {
                const int index = int(threads_.size()) + 1;
                threads_.emplace_back([this, index] { serve(index); });
            }
            job_ = &job;
            wanted_ = workers - 1;
            pending_.store(workers - 1, std::memory_order_relaxed);
            error_ = nullptr;
            generation_.fetch_add(1, std::memory_order_release);
        }
        wake_.notify_all();
        std::exception_ptr error;
        try {
            job(0);
        } catch (...) {
            error = std::current_exception();
        }
        spin_until([this] { return pending_.load(std::memory_order_acquire) == 0; });
        std::unique_lock<std::mutex> lock(state_);
        finished_.wait(lock, [this] { return pending_.load(std::memory_order_relaxed) == 0; });
        job_ = nullptr;
        if (!error) error = error_;
        lock.unlock();
        if (error) std::rethrow_exception(error);
        return true;
    }

private:
    // Worker `index` (1-based) runs every loop that wants at least `index`
    // workers; the kept threads live as long as the process.
    [[noreturn]] void serve(int index) {
        uint64_t seen = 0;
        std::unique_lock<std::mutex> lock(state_);
        for (;;) {
            if (generation_.load(std::memory_order_relaxed) == seen) {
                lock.unlock();
                spin_until([&] { return generation_.load(std::memory_order_acquire) != seen; });
                lock.lock();
            }
            wake_.wait(lock, [&] { return generation_.load(std::memory_order_relaxed) != seen; });
            seen = generation_.load(std::memory_order_relaxed);
            if (index > wanted_) continue;
            const std::function<void(int)>* job = job_;
            lock.unlock();
            std::exception_ptr error;
            try {
                (*job)(index);
            } catch (...) {
                error = std::current_exception();
            }
            lock.lock();
            if (error && !error_) error_ = error;
            if (pending_.fetch_sub(1, std::memory_order_acq_rel) == 1) finished_.notify_one();
        }
    }

    std::mutex in_use_;  // held by the one loop that has the threads
    std::mutex state_;   // guards everything below
    std::condition_variable wake_, finished_;
    std::vector<std::thread> threads_;
    const std::function<void(int)>* job_ = nullptr;
    int wanted_ = 0;
    // Written under state_; atomic so that a polling thread may read them
    // without it.
    std::atomic<int> pending_{0};
    std::atomic<uint64_t> generation_{0};
    std::exception_ptr error_;
};

}  // namespace

bool run_on_kept_threads(int workers, const std::function<void(int)>& job) {
    // Never destroyed: the workers sleep until the process ends, and no
    // destructor has to race a job started from another static's destructor.
    static KeptThreads* const kept = new KeptThreads;
#if defined(__unix__)
    // A child forked after the threads started has their state but not the
    // threads (fork copies only the calling thread): it would wait for them
    // for ever, so it runs on threads of its own.
    static const pid_t owner = ::getpid();
    if (::getpid() != owner) return false;
#endif
    return kept->run(workers, job);
}

}  // namespace vqtex::detail

namespace vqtex {

void run_together(int workers, const std::function<void(int)>& job) {
    if (workers <= 1) {
        job(0);
        return;
    }
    if (detail::run_on_kept_threads(workers, job)) return;
    // The kept threads are busy (a call from another thread, or from inside
    // a job): threads of this call's own, with the same error rule.
    std::vector<std::exception_ptr> errors(static_cast<std::size_t>(workers));
    const auto guarded = [&](int w) {
        try {
            job(w);
        } catch (...) {
            errors[std::size_t(w)] = std::current_exception();
        }
    };
    std::vector<std::thread> pool;
    for (int w = 1; w < workers; ++w) pool.emplace_back(guarded, w);
    guarded(0);
    for (auto& t : pool) t.join();
    for (const auto& e : errors)
        if (e) std::rethrow_exception(e);
}

}  // namespace vqtex

// A forked child per measured run (see measured_run.hpp).
#include "measured_run.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>

namespace vqtex_tools {
namespace {

// A field of /proc/self/status, in KiB.
long status_kib(const char* field) {
    std::ifstream f("/proc/self/status");
    std::string line;
    while (std::getline(f, line))
        if (line.rfind(field, 0) == 0) return std::atol(line.c_str() + std::strlen(field));
    return 0;
}

}  // namespace

// Runs `work` in a forked child, so that every encode and decode is measured
// on its own: the peak memory it added (the child's high-water mark minus
// what it inherited) and its wall time. The child reports through files.
bool measured(const std::function<bool()>& work, long& peak_kib, double& seconds) {
    const auto start = std::chrono::steady_clock::now();
    std::fflush(nullptr);
    int pipe_fds[2];
    if (::pipe(pipe_fds) != 0) return false;
    const pid_t pid = ::fork();
    if (pid < 0) return false;
    if (pid == 0) {
        ::close(pipe_fds[0]);
        const long base = status_kib("VmRSS:");
        const bool ok = work();
        const long added = status_kib("VmHWM:") - base;
        if (::write(pipe_fds[1], &added, sizeof added) != ssize_t(sizeof added)) ::_exit(2);
        ::_exit(ok ? 0 : 1);
    }
    ::close(pipe_fds[1]);
    long added = 0;
    const bool got = ::read(pipe_fds[0], &added, sizeof added) == ssize_t(sizeof added);
    ::close(pipe_fds[0]);
    int status = 0;
    if (::waitpid(pid, &status, 0) < 0) return false;
    peak_kib = got ? added : 0;
    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

std::vector<uint8_t> read_all(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    return std::vector<uint8_t>((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
}

bool write_all(const std::string& path, const uint8_t* data, std::size_t n) {
    std::ofstream f(path, std::ios::binary);
    f.write(reinterpret_cast<const char*>(data), std::streamsize(n));
    return bool(f);
}

}  // namespace vqtex_tools

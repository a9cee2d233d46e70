// batch.cpp - the programs' batch mode (see batch.hpp).
#include "batch.hpp"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <thread>

#include "cli_common.hpp"
#include "image_io.hpp"

namespace vqtex_tools {

namespace fs = std::filesystem;

namespace {

std::string lower(std::string s) {
    for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
    return s;
}

}  // namespace

std::vector<std::string> expand_inputs(const std::vector<std::string>& args,
                                       const std::vector<std::string>& extensions) {
    std::vector<std::string> out;
    for (const std::string& arg : args) {
        std::error_code ec;
        if (!fs::is_directory(arg, ec)) {
            out.push_back(arg);
            continue;
        }
        std::vector<std::string> found;
        for (const auto& e : fs::directory_iterator(arg, ec)) {
            const std::string name = e.path().filename().string();
            if (!e.is_regular_file(ec) || name.empty() || name[0] == '.') continue;
            const std::string ext = lower(e.path().extension().string());
            if (std::find(extensions.begin(), extensions.end(), ext) != extensions.end())
                found.push_back(e.path().string());
        }
        std::sort(found.begin(), found.end());
        if (found.empty()) found.push_back(arg);
        out.insert(out.end(), found.begin(), found.end());
    }
    return out;
}

std::string batch_output_name(const std::string& input, const std::string& out_dir, const std::string& suffix,
                              const std::string& ext) {
    const std::string dotted = ext.empty() || ext[0] == '.' ? ext : "." + ext;
    return (fs::path(out_dir) / (fs::path(input).stem().string() + suffix + dotted)).string();
}

void check_batch_pair(const std::string& input, const std::string& output, const std::string& kind) {
    std::error_code ec;
    if (fs::is_directory(input, ec))
        throw std::runtime_error("folder '" + input + "' holds no " + kind + ": give files, or a folder of them");
    if (fs::exists(output, ec) && fs::equivalent(input, output, ec))
        throw std::runtime_error(input + ": its output '" + output +
                                 "' is the input itself: choose another -o folder, --suffix or --format");
}

void prepare_output_folder(const std::string& out_dir) {
    std::error_code ec;
    if (fs::is_directory(out_dir, ec)) return;
    if (fs::exists(out_dir, ec))
        throw std::runtime_error("output folder '" + out_dir + "' is a file: give a folder to -o");
    fs::create_directories(out_dir, ec);
    if (ec) throw std::runtime_error("cannot create output folder '" + out_dir + "': " + ec.message());
}

const std::vector<std::string>& image_extensions() {
    static const std::vector<std::string> exts{".png", ".jpg", ".jpeg", ".tif", ".tiff", ".exr", ".tga",
                                               ".bmp", ".webp", ".hdr", ".ppm", ".pgm", ".pnm", ".gif"};
    return exts;
}

ThreadShare share_threads(unsigned jobs, std::size_t files) {
    if (jobs == 0) jobs = std::max(1u, std::thread::hardware_concurrency());
    ThreadShare s;
    s.workers = unsigned(std::clamp<std::size_t>(files, 1, jobs));
    // Files first (they scale perfectly); cores left over go inside them.
    s.per_file = std::max(1u, jobs / s.workers);
    return s;
}

std::string json_line(const nlohmann::ordered_json& object) {
    return object.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n";
}

namespace {

// The batch's progress bar on stderr (a terminal only).
class BatchBar {
public:
    BatchBar(bool on, std::size_t total) : on_(on && ::isatty(2)), total_(total) {}
    void draw(std::size_t done, std::size_t failed) {
        if (!on_) return;
        constexpr int kWidth = 30;
        const int filled = int(double(done) / double(total_) * kWidth);
        char line[160];
        std::snprintf(line, sizeof line, "\r[%.*s%*s] %zu/%zu files%s", filled, "##############################",
                      kWidth - filled, "", done, total_, failed ? (", " + std::to_string(failed) + " failed").c_str() : "");
        write_stderr(line);
        drawn_ = true;
    }
    void clear() {
        if (drawn_) write_stderr("\r" + std::string(70, ' ') + "\r");
        drawn_ = false;
    }

private:
    bool on_;
    std::size_t total_;
    bool drawn_ = false;
};

struct Outcome {
    bool ok = false;
    FileReport report;
    std::string error;
};

}  // namespace

int run_batch(std::size_t files, const BatchOptions& options, const FileWork& work) {
    const ThreadShare share = share_threads(options.jobs, files);
    std::vector<std::optional<Outcome>> outcomes(files);
    std::mutex mutex;
    std::size_t next_to_print = 0, done = 0, failed = 0;
    BatchBar bar(options.progress && !options.quiet && !options.json, files);
    std::atomic<std::size_t> next{0};

    // Prints every finished outcome whose predecessors are printed, so the
    // output is in input order whatever the order of completion.
    auto flush_in_order = [&] {
        bar.clear();
        while (next_to_print < files && outcomes[next_to_print]) {
            const Outcome& o = *outcomes[next_to_print];
            if (!o.ok) {
                write_stderr(std::string(options.program) + ": error: " + o.error + "\n");
                if (options.json && options.names) {
                    const nlohmann::ordered_json j{{options.name_key, (*options.names)[next_to_print]},
                                                   {"error", o.error}};
                    std::fputs(json_line(j).c_str(), stdout);
                }
            } else if (options.json) {
                std::fputs(json_line(o.report.json).c_str(), stdout);
            } else if (!options.quiet && !o.report.text.empty()) {
                std::fputs(o.report.text.c_str(), stdout);
            }
            std::fflush(stdout);
            outcomes[next_to_print]->report = FileReport{};  // printed: its memory goes now
            ++next_to_print;
        }
        bar.draw(done, failed);
    };

    auto worker = [&] {
        for (std::size_t i; (i = next.fetch_add(1)) < files;) {
            Outcome o;
            try {
                o.report = work(i, share.per_file);
                o.ok = true;
            } catch (const std::exception& e) {
                o.error = e.what();
            }
            const std::lock_guard<std::mutex> lock(mutex);
            ++done;
            if (!o.ok) ++failed;
            outcomes[i] = std::move(o);
            flush_in_order();
        }
    };
    if (share.workers <= 1) {
        worker();
    } else {
        std::vector<std::thread> pool;
        for (unsigned w = 0; w < share.workers; ++w) pool.emplace_back(worker);
        for (auto& t : pool) t.join();
    }
    bar.clear();
    return failed ? 1 : 0;
}

void BatchOutputs::add(const std::string& output) {
    outputs_.push_back(output);
    first_.emplace(output, outputs_.size() - 1);
}

void BatchOutputs::check_first(std::size_t i, const char* verb) const {
    const std::size_t first = first_.at(outputs_[i]);
    if (first != i)
        throw std::invalid_argument(inputs_[i] + ": its output '" + outputs_[i] + "' is also the output of '" +
                                    inputs_[first] + "': rename one, or " + verb + " them in separate calls");
}

BatchOptions batch_options(const char* program, unsigned jobs, bool json, bool quiet,
                           const std::vector<std::string>& inputs) {
    BatchOptions options;
    options.program = program;
    options.jobs = jobs;
    options.json = json;
    options.names = &inputs;
    options.quiet = quiet;
    return options;
}

void print_report(const FileReport& report, bool json, bool quiet) {
    if (json)
        std::fputs(json_line(report.json).c_str(), stdout);
    else if (!quiet)
        std::fputs(report.text.c_str(), stdout);
}

void require_single_pair(const std::vector<std::string>& files, const std::string& output, const std::string& verb,
                         const std::string& inputs) {
    if (files.size() < 2)
        throw std::invalid_argument("give an " + output + " after '" + files[0] + "', or -o DIR to " + verb +
                                    " into a folder");
    if (files.size() > 2) throw std::invalid_argument("several " + inputs + " need -o DIR for their outputs");
    // Writing the output would replace the input (the write is atomic, so
    // nothing would be left of it).
    std::error_code ec;
    if (fs::exists(files[1], ec) && fs::equivalent(files[0], files[1], ec))
        throw std::invalid_argument("'" + files[1] + "' is the input itself: give another " + output +
                                    ", or the input would be replaced");
}

}  // namespace vqtex_tools

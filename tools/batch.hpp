// batch.hpp - many files per call for the programs (asset pipelines): input
// lists and folders, output names in an output folder, a bounded pool of
// workers that shares the cores between files and within a file, reports in
// input order (text or JSON lines), one line per failed file.
#pragma once

#include <cstddef>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace vqtex_tools {

// Files as given; each folder replaced by its regular files (not hidden)
// whose extension, lower-cased and with its dot, is in `extensions`, sorted
// by name. A folder with no such file, or a missing path, stays as it is so
// that its own error names it.
std::vector<std::string> expand_inputs(const std::vector<std::string>& args,
                                       const std::vector<std::string>& extensions);

// OUT_DIR/STEM SUFFIX.EXT for `input` ("stone.vqt", "out", "_1k", "png" ->
// "out/stone_1k.png").
std::string batch_output_name(const std::string& input, const std::string& out_dir, const std::string& suffix,
                              const std::string& ext);

// Throws a one-line reason when a batch cannot process `input` into
// `output`: the input is a folder that held no file of the kind sought
// (`kind`, e.g. ".vqt file"), or the output would overwrite the input.
void check_batch_pair(const std::string& input, const std::string& output, const std::string& kind);

// Creates `out_dir` when missing; throws a one-line reason when it cannot.
void prepare_output_folder(const std::string& out_dir);

// Image file extensions the encoder's folder expansion picks up.
const std::vector<std::string>& image_extensions();

// One file's result: a line (or lines) for people and an object for --json.
struct FileReport {
    std::string text;
    nlohmann::ordered_json json;
};

// Work on file `index` with `threads` library threads; throws
// std::exception with a one-line message on failure.
using FileWork = std::function<FileReport(std::size_t index, unsigned threads)>;

// How many files run at once and with how many library threads each, for
// `jobs` threads (0: all cores) over `files` files: every core busy, never
// more threads than `jobs`.
struct ThreadShare {
    unsigned workers = 1, per_file = 1;
};
ThreadShare share_threads(unsigned jobs, std::size_t files);

struct BatchOptions {
    const char* program = "";  // names the program in error lines
    unsigned jobs = 0;
    bool json = false;         // print FileReport::json as JSON lines
    bool quiet = false;        // print nothing but errors
    bool progress = true;      // a bar over the batch, on a terminal
    // With json, a failed file also gets a line {KEY: name, "error": MESSAGE}
    // on stdout, so that a pipeline reading the JSON lines sees every file.
    const std::vector<std::string>* names = nullptr;
    const char* name_key = "input";
};

// Runs `work` for files 0 .. files-1 on a bounded pool. Reports go to
// stdout in input order; a failure prints "PROGRAM: error: MESSAGE" on
// stderr (and its JSON line, see BatchOptions) and the others go on. Returns the exit status: 0, or 1 when any
// file failed.
int run_batch(std::size_t files, const BatchOptions& options, const FileWork& work);

// A batch's outputs, one per input, and the first input to claim each
// name: a later input that would write the same file fails with a one-line
// error instead of replacing the first one's output.
class BatchOutputs {
public:
    explicit BatchOutputs(const std::vector<std::string>& inputs) : inputs_(inputs) {}
    void add(const std::string& output);
    const std::string& operator[](std::size_t i) const { return outputs_[i]; }
    // Throws for input i when an earlier input claimed its output; `verb`
    // says what separate calls would do ("decode", "encode" ...).
    void check_first(std::size_t i, const char* verb) const;

private:
    const std::vector<std::string>& inputs_;
    std::vector<std::string> outputs_;
    std::map<std::string, std::size_t> first_;
};

// The options of a program's batch over `inputs`, named in its error lines.
BatchOptions batch_options(const char* program, unsigned jobs, bool json, bool quiet,
                           const std::vector<std::string>& inputs);

// Without -o DIR a call takes one input and its output: throws the one-line
// error that says what is missing or too many (`output` names the output,
// `verb` what a folder would receive, `inputs` what the inputs are).
void require_single_pair(const std::vector<std::string>& files, const std::string& output, const std::string& verb,
                         const std::string& inputs);

// A single file's report on stdout: its JSON line, its text, or nothing.
void print_report(const FileReport& report, bool json, bool quiet);

// One JSON line; bytes that are not UTF-8 (file names may hold any) become
// U+FFFD instead of failing.
std::string json_line(const nlohmann::ordered_json& object);

}  // namespace vqtex_tools

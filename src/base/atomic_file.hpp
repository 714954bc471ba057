// The one way carve writes an output: everything (G-code, stats, report, SVG, raster, zip) goes
// to a temporary in the target's own folder, is flushed and fsync'ed, and is renamed onto the
// target only when complete. The temporary is removed on any error (destructor) and on SIGINT,
// SIGTERM and SIGHUP (install_cleanup_handlers); after a SIGKILL or a crash the next run of
// carve removes it (remove_stale_temporaries), recognising the name ".carve-tmp-<pid>-XXXXXX"
// whose process is gone. The name is short and independent of the target's, so a target name
// near NAME_MAX still works, and two runs never share a temporary.
// Bottom layer: depends on nothing else of carve.
#pragma once

#include <cstdio>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace carve {

// SIGINT, SIGTERM, SIGHUP remove every registered temporary, then end the process with the
// signal's own status. Call once at the start of main().
void install_cleanup_handlers();

// --timeout: after `seconds` of wall time, removes every registered temporary, says so on
// stderr and ends the process with exit status 1 (a refused input). A timer signal and not a
// check between stages: a stage that runs away never reaches the next check.
void exit_after(double seconds);

// Removes temporaries ".carve-tmp-<pid>-*" in `dir` whose process no longer exists.
void remove_stale_temporaries(const std::string& dir);

// A read-write temporary file in the folder of `near_path`, unlinked at once (it disappears with
// the process whatever happens). Throws OutputError naming `what`.
std::FILE* unlinked_temporary(const std::string& near_path, const std::string& what);

// Something complete under a temporary name, waiting to be renamed onto its target.
class PendingOutput {
  public:
    virtual ~PendingOutput() = default;
    virtual void commit() = 0;
};

class AtomicFile final : public PendingOutput {
  public:
    // Creates the temporary next to `target`. Throws OutputError if the folder is not writable
    // or the target exists and is not a regular file.
    explicit AtomicFile(std::string target);
    ~AtomicFile() override;  // removes the temporary unless committed
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;

    std::FILE* stream();  // buffered, on the temporary; check write errors with write()/close()
    void write(std::string_view data);  // throws OutputError on a short write
    // Flushes, fsyncs and closes: the temporary is complete. Throws OutputError.
    void close();
    // close() if not yet done, then renames onto the target (and fsyncs the folder).
    void commit() override;
    const std::string& target() const { return target_; }
    const std::string& temporary() const { return temp_; }

  private:
    [[noreturn]] void fail(const std::string& why);
    std::string target_, temp_;
    std::FILE* file_ = nullptr;
    int slot_ = -1;
    bool committed_ = false;
};

// A folder of outputs (layer pictures, a raster stack): the files are written into a temporary
// folder next to the target; commit() moves them into the target folder (created if missing,
// files of the same names replaced, other files left alone) and removes the temporary folder.
// Until then, and on any error or signal, nothing of the run is in the target.
class AtomicDir final : public PendingOutput {
  public:
    explicit AtomicDir(std::string target);
    ~AtomicDir() override;  // removes the temporary folder and its files unless committed
    AtomicDir(const AtomicDir&) = delete;
    AtomicDir& operator=(const AtomicDir&) = delete;

    const std::string& folder() const { return temp_; }  // write the files here
    void commit() override;
    const std::string& target() const { return target_; }

  private:
    std::string target_, temp_;
    int slot_ = -1;
    bool committed_ = false;
};

// Outputs of one run held back until every one of them is complete, then renamed in a row, so
// that a run failing late leaves none of its outputs behind (and no temporary).
class OutputGroup {
  public:
    void hold(std::unique_ptr<PendingOutput> output) { pending_.push_back(std::move(output)); }
    void commit_all();
    // Moves every output held to `other`, committed with its own (the plates of a --cut).
    void hand_over(OutputGroup& other);

  private:
    std::vector<std::unique_ptr<PendingOutput>> pending_;
};

// Writes `text` to `path` atomically (or into `group`, committed with it).
void write_file_atomically(const std::string& path, std::string_view text,
                           OutputGroup* group = nullptr);

}  // namespace carve

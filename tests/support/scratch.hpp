// A scratch folder for one test program's files, removed when the program ends: ctest runs each
// test as a process of its own, and folders left behind piled up in /tmp (some 400 a suite run,
// 9,400 after a few days here, which every carve run's scan for stale temporaries then read).
#pragma once

#include <unistd.h>

#include <filesystem>
#include <string>
#include <system_error>

namespace carve::test {

class ScratchDir {
  public:
    explicit ScratchDir(const std::string& prefix)
        : path_(std::filesystem::temp_directory_path() / (prefix + std::to_string(::getpid()))) {
        std::filesystem::create_directories(path_);
    }
    ~ScratchDir() {
        // A forked child that returns here instead of exec'ing must not take the parent's files.
        if (::getpid() != owner_) return;
        std::error_code ec;
        std::filesystem::remove_all(path_, ec);
    }
    ScratchDir(const ScratchDir&) = delete;
    ScratchDir& operator=(const ScratchDir&) = delete;
    const std::filesystem::path& path() const { return path_; }

  private:
    std::filesystem::path path_;
    pid_t owner_ = ::getpid();
};

}  // namespace carve::test

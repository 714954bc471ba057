// Runs an upstream stage on its own thread and hands its layers over through a bounded queue,
// so that the carving sweep and the toolpath/G-code stages use both cores. Layers keep their
// order, so the output does not depend on the number of threads.
#pragma once

#include <condition_variable>
#include <deque>
#include <exception>
#include <mutex>
#include <thread>

#include "carving/partition.hpp"

namespace carve {

class ThreadedSource : public LayerSource {
  public:
    // Starts pulling from `upstream` at once; at most `capacity` layers wait in the queue, so
    // memory stays bounded whatever the model's height. A few layers cost ten times the
    // others (where the slices change fast: the tops of fandisk's faces), and with room for
    // 16 the stages after them keep working meanwhile: fandisk's wall time 1.51 -> 1.40 s
    // against 4 (5 alternating runs, CPU the same), peak memory 20.0 MB at --scale 2.5.
    ThreadedSource(LayerSource& upstream, size_t capacity = 16);
    ~ThreadedSource() override;  // stops and joins the worker
    ThreadedSource(const ThreadedSource&) = delete;
    ThreadedSource& operator=(const ThreadedSource&) = delete;

    // The next layer; rethrows here an exception raised upstream.
    std::optional<LayerPartition> next() override;

  private:
    void run();

    LayerSource& upstream_;
    size_t capacity_;
    std::mutex mutex_;
    std::condition_variable changed_;
    std::deque<LayerPartition> queue_;
    bool done_ = false, stop_ = false;
    std::exception_ptr error_;
    std::thread worker_;
};

}  // namespace carve

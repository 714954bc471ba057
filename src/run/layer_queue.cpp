// The worker thread of ThreadedSource.
#include "run/layer_queue.hpp"

namespace carve {

ThreadedSource::ThreadedSource(LayerSource& upstream, size_t capacity)
    : upstream_(upstream), capacity_(capacity < 1 ? 1 : capacity), worker_([this] { run(); }) {}

ThreadedSource::~ThreadedSource() {
    {
        std::lock_guard lock(mutex_);
        stop_ = true;
    }
    changed_.notify_all();
    worker_.join();
}

void ThreadedSource::run() {
    try {
        while (true) {
            {
                std::unique_lock lock(mutex_);
                changed_.wait(lock, [&] { return stop_ || queue_.size() < capacity_; });
                if (stop_) break;
            }
            std::optional<LayerPartition> layer = upstream_.next();
            std::lock_guard lock(mutex_);
            if (!layer) break;
            queue_.push_back(std::move(*layer));
            changed_.notify_all();
        }
    } catch (...) {
        std::lock_guard lock(mutex_);
        error_ = std::current_exception();
    }
    std::lock_guard lock(mutex_);
    done_ = true;
    changed_.notify_all();
}

std::optional<LayerPartition> ThreadedSource::next() {
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [&] { return !queue_.empty() || done_; });
    if (!queue_.empty()) {
        LayerPartition layer = std::move(queue_.front());
        queue_.pop_front();
        changed_.notify_all();
        return layer;
    }
    if (error_) std::rethrow_exception(error_);
    return std::nullopt;
}

}  // namespace carve

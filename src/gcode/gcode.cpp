// G-code assembly: spill layers as they come (top down), write them bottom up at the end.
//
// Layers are spilled in a compact binary form (zig-zag varint deltas) to an unlinked temporary
// file next to the output, so nothing is left behind even if the process dies. finish() runs the
// emitter once over the spilled layers, writing the body to a second unlinked file while it
// measures (time, material, bounds); then the header stating those figures, the body and the
// trailer go to a temporary name that is renamed onto the output when complete. The figures
// come from the very moves written, so the header cannot disagree with the body. (A measuring
// pass before the writing pass did the same in twice the time, all of it after the last layer,
// when nothing else runs.) That pass runs in chunks of layers on several threads, each from the
// state the layers before it leave (emitter.hpp, "chunks"): a chunk whose start was not the
// state the chunk before it ended in is written again after it, so the file is the same bytes
// whatever the number of threads.
#include "gcode/gcode.hpp"

#include <fmt/format.h>
#include <sys/stat.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>

#include "base/atomic_file.hpp"
#include "base/error.hpp"
#include "base/numbers.hpp"
#include "base/stage_timer.hpp"
#include "gcode/emitter.hpp"
#include "gcode/header.hpp"
#include "gcode/labels.hpp"
#include "gcode/progress.hpp"
#include "gcode/safe_text.hpp"
#include "gcode/spill.hpp"

namespace carve {

std::string format_duration(double seconds) {
    long long s = std::llround(std::max(0.0, seconds));
    const long long d = s / 86400, h = s / 3600 % 24, m = s / 60 % 60, sec = s % 60;
    if (d > 0) return fmt::format("{}d {}h {}m {}s", d, h, m, sec);
    if (h > 0) return fmt::format("{}h {}m {}s", h, m, sec);
    if (m > 0) return fmt::format("{}m {}s", m, sec);
    return fmt::format("{}s", sec);
}

namespace {

// A read-write temporary file next to `path` (same disk, and a bad directory fails early),
// unlinked at once so that it disappears with the process whatever happens. Its name is
// carve's short temporary pattern, not `path` plus a suffix: a target name near the file
// system's limit still works.
std::FILE* unlinked_file(const std::string& path, const char*) {
    return unlinked_temporary(path, path);
}

// What is printed (the model and what carve adds round it: supports, brim, skirt) stays on the
// bed and under the printer's height, or nothing is written. The run refuses a model too large
// before slicing; this sees every extrusion, so it also holds what is added round the model.
// The extents are the lines' centres, compared with a micrometre of slack for rounding.
void refuse_beyond_machine(const Settings& s, const Bounds& b) {
    if (!s.bed_check || b.empty()) return;
    const double slack = 1e-3;
    // The printer's Z: the layers' heights and the offset added to them.
    if (b.max_z + s.z_offset > s.max_print_height + slack)
        throw InputError(fmt::format(
            "the print reaches z = {:.2f} mm{}, above the {} mm the printer prints "
            "(--max-print-height, a profile's max_print_height); scale the model down, choose a "
            "taller printer, or pass --no-bed-check",
            b.max_z + s.z_offset,
            s.z_offset != 0 ? fmt::format(" with --z-offset {}", plain_number(s.z_offset)) : "",
            plain_number(s.max_print_height)));
    // Every other Z written: lifts on travel, the custom G-code's moves (issue #52).
    if (b.max_move_z > s.max_print_height + slack)
        throw InputError(fmt::format(
            "{} reaches z = {:.2f} mm, above the {} mm the printer prints (--max-print-height, "
            "a profile's max_print_height); lower it, choose a taller printer, or pass "
            "--no-bed-check",
            b.max_move_what, b.max_move_z, plain_number(s.max_print_height)));
    if (b.min_x < -slack || b.min_y < -slack || b.max_x > s.bed_x + slack ||
        b.max_y > s.bed_y + slack)
        throw InputError(fmt::format(
            "the print reaches from ({:.2f}, {:.2f}) to ({:.2f}, {:.2f}) mm, beyond the {} x {} "
            "mm bed; scale the model down, choose a larger --bed, or pass --no-bed-check",
            b.min_x, b.min_y, b.max_x, b.max_y, plain_number(s.bed_x), plain_number(s.bed_y)));
}

// finish()'s pieces, defined with its phases below.
struct Chunk;
struct ChunkSums;

}  // namespace

struct GcodeWriter::Impl {
    std::string output_path;
    std::string written;  // where the complete file is (written_path())
    Settings settings;
    Coord off_x = 0, off_y = 0;
    int layer_count = 0;  // the print's layers, a raft's included
    int first = 0;        // the first one's index (Settings::first_print_layer)
    std::FILE* spill = nullptr;
    long long spill_end = 0;
    std::vector<long long> offsets, sizes;
    // Layers whose order does not depend on where the layer below ended (one island or none):
    // the state after them is theirs alone, so the chunks start after them where they can.
    std::vector<char> settled;
    OutputGroup* group = nullptr;         // commit held back until the run's other outputs are done
    std::string object = "object";        // the object's label
    std::vector<ObjectLabel> objects;     // several objects, or none
    std::vector<std::string> thumbnails;  // the header's thumbnail blocks
    bool finished = false;
    int threads = 1;
    ChunkCount chunk_count;
    std::mutex mutex;

    // finish()'s phases, in order (below, after Chunk).
    std::vector<int> chunk_starts(int count) const;
    std::vector<Chunk*> open_chunks(std::vector<Chunk>& chunks) const;
    void write_chunk(Chunk& c) const;
    int64_t write_chunks(const std::vector<Chunk*>& tasks) const;
    void reconcile(std::vector<Chunk>& chunks, size_t k);
    ChunkSums sum_chunks(std::vector<Chunk>& chunks);
    void assemble(std::vector<Chunk>& chunks, const std::vector<std::string>& header_comments,
                  const ChunkSums& sums);

    // The layer in the print's `slot` (from 0 at the bottom). Thread-safe: pread, no shared
    // file position.
    LayerToolpaths load(int slot) const {
        if (offsets[slot] < 0) {
            LayerToolpaths empty;
            empty.index = slot + first;
            empty.z = settings.layer_top_mm(empty.index);
            return empty;
        }
        std::string blob(static_cast<size_t>(sizes[slot]), '\0');
        size_t got = 0;
        while (got < blob.size()) {
            const ssize_t n = pread(fileno(spill), blob.data() + got, blob.size() - got,
                                    offsets[slot] + static_cast<long long>(got));
            if (n <= 0) throw std::runtime_error("carve: cannot read back the layer spill file");
            got += static_cast<size_t>(n);
        }
        return decode_layer(blob);
    }

    std::unique_ptr<Emitter> emitter(std::FILE* out) const {
        auto e = std::make_unique<Emitter>(settings, off_x, off_y, out, output_path, object);
        if (!objects.empty()) e->set_objects(objects);
        return e;
    }

    // The comment lines before the body, in PrusaSlicer's order: who made the file first
    // (hosts look there), the thumbnails, then Cura's summary lines and carve's own; the
    // figures and the configuration close the file (tail()), where Moonraker's PrusaSlicer
    // parser reads them.
    std::vector<std::string> head(const std::vector<std::string>& comments, const PrintStats& s,
                                  const Bounds& b, const std::vector<Bounds>& each) const {
        std::vector<std::string> lines{generated_by_line(), ";"};
        for (const std::string& t : thumbnails) lines.push_back(comment_text(t));
        // The comments hold the model's name, which whoever named the file chose.
        for (const std::string& c : comments)
            lines.push_back(comment_text(c.rfind(';', 0) == 0 ? c : "; " + c));
        lines.push_back(fmt::format(";FLAVOR:{}", flavor_name(settings.flavor)));
        lines.push_back(fmt::format(";TIME:{}", std::llround(s.estimated_print_time_s)));
        lines.push_back(fmt::format(";Filament used: {:.5f}m", s.filament_length_mm / 1000.0));
        lines.push_back(fmt::format(";Layer height: {}", settings.layer_height));
        if (!b.empty()) {
            lines.push_back(fmt::format(";MINX:{:.3f}", b.min_x));
            lines.push_back(fmt::format(";MINY:{:.3f}", b.min_y));
            lines.push_back(fmt::format(";MINZ:{:.3f}", b.min_z));
            lines.push_back(fmt::format(";MAXX:{:.3f}", b.max_x));
            lines.push_back(fmt::format(";MAXY:{:.3f}", b.max_y));
            lines.push_back(fmt::format(";MAXZ:{:.3f}", b.max_z));
        }
        lines.push_back(fmt::format(";LAYER_COUNT:{}", layer_count));
        lines.push_back(fmt::format("; estimated printing time (normal mode) = {}",
                                    format_duration(s.estimated_print_time_s)));
        if (settings.silent_mode)
            lines.push_back(fmt::format("; estimated printing time (silent mode) = {}",
                                        format_duration(s.estimated_stealth_time_s)));
        // A Klipper without [pause_resume] and a PAUSE macro reports an unknown command and
        // prints on: the file says what it needs.
        if (settings.flavor == GcodeFlavor::Klipper && !settings.pause_at.empty() &&
            (settings.pause_command.empty() || settings.pause_command == "PAUSE"))
            lines.push_back(
                "; --pause-at writes PAUSE: Klipper pauses only with [pause_resume] and a PAUSE "
                "macro in printer.cfg (Mainsail's and Fluidd's client macros define one); "
                "--pause-command names another");
        if (!objects.empty()) {
            const bool klipper = settings.flavor == GcodeFlavor::Klipper;
            for (size_t k = 0; k < objects.size() && k < each.size(); ++k) {
                const Bounds& o = each[k];
                if (o.empty() || (!klipper && k > 0)) continue;
                for (const std::string& l :
                     object_definition(settings, objects[k].name, o.min_x, o.min_y, o.max_x,
                                       o.max_y, static_cast<int>(objects.size())))
                    lines.push_back(l);
            }
        } else if (!b.empty()) {
            // The object's own extent: the skirt and brim are printed outside its block.
            const Bounds& o = !each.empty() && !each[0].empty() ? each[0] : b;
            for (const std::string& l :
                 object_definition(settings, object, o.min_x, o.min_y, o.max_x, o.max_y))
                lines.push_back(l);
        }
        lines.push_back("");
        return lines;
    }

    // After the body: PrusaSlicer's closing figures, then the configuration block.
    std::vector<std::string> tail(const PrintStats& s) const {
        std::vector<std::string> lines{""};
        for (const std::string& l : footer_figures(s, layer_count)) lines.push_back(l);
        lines.push_back("");
        for (const std::string& l : config_block(settings)) lines.push_back(l);
        return lines;
    }
};

GcodeWriter::GcodeWriter(std::string output_path, const Settings& settings, double offset_x_mm,
                         double offset_y_mm, int layer_count)
    : impl_(std::make_unique<Impl>()) {
    Impl& m = *impl_;
    m.output_path = std::move(output_path);
    m.settings = settings;
    m.off_x = to_units(offset_x_mm);
    m.off_y = to_units(offset_y_mm);
    m.first = settings.first_print_layer();
    m.layer_count = std::max(0, layer_count);
    m.offsets.assign(m.layer_count, -1);
    m.sizes.assign(m.layer_count, 0);
    m.settled.assign(m.layer_count, 1);
    // The spill lives next to the output (same disk, and a bad directory fails early), unlinked
    // at once so that it disappears with the process whatever happens.
    m.spill = unlinked_file(m.output_path, ".spill-XXXXXX");
}

GcodeWriter::~GcodeWriter() {
    if (!impl_) return;
    if (impl_->spill) std::fclose(impl_->spill);
}

const std::string& GcodeWriter::written_path() const {
    return impl_->written;
}

void GcodeWriter::commit_with(OutputGroup& group) {
    impl_->group = &group;
}

void GcodeWriter::set_object_name(const std::string& name) {
    impl_->object = name.empty() ? "object" : name;
}

void GcodeWriter::set_objects(std::vector<ObjectLabel> objects) {
    impl_->objects = std::move(objects);
}

void GcodeWriter::set_thumbnails(std::vector<std::string> lines) {
    impl_->thumbnails = std::move(lines);
}

void GcodeWriter::add_layer(const LayerToolpaths& layer) {
    StageTimer timer(Stage::kGcode);
    const std::string blob = encode_layer(layer);
    std::lock_guard lock(impl_->mutex);
    Impl& m = *impl_;
    if (m.finished) throw std::logic_error("GcodeWriter::add_layer after finish()");
    const int slot = layer.index - m.first;
    if (slot < 0 || slot >= m.layer_count)
        throw std::out_of_range("GcodeWriter::add_layer: layer index out of range");
    if (fseeko(m.spill, m.spill_end, SEEK_SET) != 0 ||
        std::fwrite(blob.data(), 1, blob.size(), m.spill) != blob.size())
        io_error(std::strerror(errno), m.output_path + " (temporary layer file)");
    m.offsets[size_t(slot)] = m.spill_end;
    m.settled[size_t(slot)] = layer.island_starts.size() < 3;
    m.sizes[size_t(slot)] = static_cast<long long>(blob.size());
    m.spill_end += static_cast<long long>(blob.size());
}

void GcodeWriter::set_threads(int threads) {
    impl_->threads = std::max(1, threads);
}

GcodeWriter::ChunkCount GcodeWriter::chunk_count() const {
    return impl_->chunk_count;
}

namespace {

// Layers before a chunk that its emitter writes to nowhere first. The chunks start two layers
// after a settled one where they can: the first layer of the warm-up, settled, ends where it
// ends whatever came before it; the second then starts from where it truly starts, and so its
// time, which decides its speed when cooling slows it down, is its true time too.
constexpr int kWarmUpLayers = 2;
// Fewer layers than this in a chunk, and the warm-up is too large a part of its work.
constexpr int kMinChunkLayers = 24;
// From this many threads on, a chunk that starts after layers of several islands is also
// written from the other guess of their order (see Chunk::other): more CPU side by side for
// fewer chunks written again one after the other, which is what many cores want. On two the
// extra work costs about what it saves.
constexpr int kTwoGuessThreads = 4;

struct ChunkFile {
    std::FILE* file = nullptr;
    ChunkFile() = default;
    ChunkFile(const ChunkFile&) = delete;
    ChunkFile& operator=(const ChunkFile&) = delete;
    ~ChunkFile() {
        if (file) std::fclose(file);
    }
};

// One chunk's layers and what its emitter measured of them (copied out, because the emitter
// of a chunk may go on to write the next one).
struct Chunk {
    int first = 0, end = 0;  // layers [first, end)
    // In a run of layers of two islands or more, the order of each follows from where the one
    // below ended, so the run goes one of two ways (on man's legs, left-right or right-left on
    // even layers), and a warm-up from nowhere picks one at random: the other is this, written
    // from a warm-up whose first layer takes the other order.
    std::unique_ptr<Chunk> other;
    bool flipped = false;
    ChunkFile body;
    std::unique_ptr<Emitter> emitter;
    Emitter::Carry entry;  // the state its layers started from
    std::vector<Emitter::Section> sections;
    std::vector<ProgressMark> marks;
    Bounds bounds;
    std::vector<Bounds> object_bounds;
    size_t custom_bytes = 0;

    void keep_figures() {
        emitter->release_text();
        sections = emitter->sections();
        marks = emitter->progress_marks();
        bounds = emitter->bounds();
        object_bounds = emitter->object_bounds();
        custom_bytes = emitter->custom_bytes();
    }
    // This chunk written as `o` was (its other guess, which held).
    void take(Chunk& o) {
        std::swap(body.file, o.body.file);
        emitter = std::move(o.emitter);
        entry = std::move(o.entry);
        sections = std::move(o.sections);
        marks = std::move(o.marks);
        bounds = o.bounds;
        object_bounds = std::move(o.object_bounds);
        custom_bytes = o.custom_bytes;
    }
};

void merge(Bounds& to, const Bounds& b) {
    to.min_x = std::min(to.min_x, b.min_x), to.max_x = std::max(to.max_x, b.max_x);
    to.min_y = std::min(to.min_y, b.min_y), to.max_y = std::max(to.max_y, b.max_y);
    to.min_z = std::min(to.min_z, b.min_z), to.max_z = std::max(to.max_z, b.max_z);
    to.moved_to(b.max_move_z, b.max_move_what);
}

// What the chunks add up to, taken in order: the totals, the extent, and the M73 marks moved from
// each chunk's own start to the file's.
struct ChunkSums {
    PrintStats totals;
    double time = 0, stealth = 0;  // the normal and the stealth mode's (M73 Q/S)
    size_t custom_bytes = 0;
    long long offset = 0;        // of the next chunk's body in the file's
    size_t sections_before = 0;  // of the chunks before the next one
    // The time before each section, all chunks through, in either mode.
    std::vector<double> section_start, stealth_start;
    Bounds bounds;
    std::vector<Bounds> object_bounds;
    std::vector<ProgressMark> marks;

    void add_sections(const Chunk& c, size_t first) {
        for (size_t i = first; i < c.sections.size(); ++i) {
            section_start.push_back(time);
            stealth_start.push_back(stealth);
            Emitter::add_stats(totals, c.sections[i].stats);
            time += c.sections[i].time_s;
            stealth += c.sections[i].stealth_time_s;
        }
    }
    void add_extent(const Chunk& c) {
        custom_bytes += c.custom_bytes;
        Emitter::check_custom_bytes(custom_bytes);
        merge(bounds, c.bounds);
        object_bounds.resize(std::max(object_bounds.size(), c.object_bounds.size()));
        for (size_t i = 0; i < c.object_bounds.size(); ++i)
            merge(object_bounds[i], c.object_bounds[i]);
    }
    // The chunk's marks on the file's offsets, sections and elapsed times; its body, `bytes`
    // long, then ends where the next one starts.
    void rebase_marks(const Chunk& c, long long bytes) {
        for (ProgressMark mark : c.marks) {
            mark.offset += offset;
            mark.section += sections_before;
            mark.elapsed_s = mark.local_s < 0 ? time : section_start[mark.section] + mark.local_s;
            mark.stealth_elapsed_s = mark.stealth_local_s < 0
                                         ? stealth
                                         : stealth_start[mark.section] + mark.stealth_local_s;
            marks.push_back(mark);
        }
        sections_before += c.sections.size();
        offset += bytes;
    }
};

}  // namespace

// Even chunks, each moved to start after the nearest settled layer within a quarter chunk.
std::vector<int> GcodeWriter::Impl::chunk_starts(int count) const {
    std::vector<int> starts{0};
    for (int k = 1; k < count; ++k) {
        const int even = int(int64_t(layer_count) * k / count);
        const int reach = layer_count / count / 4;
        int at = even;
        for (int d = 0; d <= reach; ++d) {
            if (even - d - kWarmUpLayers > starts.back() &&
                settled[size_t(even - d - kWarmUpLayers)]) {
                at = even - d;
                break;
            }
            if (even + d < layer_count && even + d - kWarmUpLayers > starts.back() &&
                settled[size_t(even + d - kWarmUpLayers)]) {
                at = even + d;
                break;
            }
        }
        starts.push_back(std::max(at, starts.back() + 1));
    }
    return starts;
}

// The chunks, each with its body file open, and the ones to write from the other guess too:
// the tasks to write side by side, in order.
std::vector<Chunk*> GcodeWriter::Impl::open_chunks(std::vector<Chunk>& chunks) const {
    const int count = int(chunks.size());
    const std::vector<int> starts = chunk_starts(count);
    std::vector<Chunk*> tasks;
    auto open_chunk = [&](Chunk& c, int from, int to) {
        c.first = from;
        c.end = to;
        c.body.file = unlinked_file(output_path, ".body-XXXXXX");
        std::setvbuf(c.body.file, nullptr, _IOFBF, 1 << 16);
        tasks.push_back(&c);
    };
    for (int k = 0; k < count; ++k) {
        Chunk& c = chunks[size_t(k)];
        open_chunk(c, starts[size_t(k)], k + 1 < count ? starts[size_t(k) + 1] : layer_count);
        if (threads >= kTwoGuessThreads && c.first >= kWarmUpLayers &&
            !settled[size_t(c.first - kWarmUpLayers)]) {
            c.other = std::make_unique<Chunk>();
            c.other->flipped = true;
            open_chunk(*c.other, c.first, c.end);
        }
    }
    return tasks;
}

// One chunk from the state its warm-up guesses (the very state for the first).
void GcodeWriter::Impl::write_chunk(Chunk& c) const {
    if (c.first == 0) {
        c.emitter = emitter(c.body.file);
        c.emitter->start();
    } else {
        c.emitter = emitter(nullptr);
        const int from = std::max(0, c.first - kWarmUpLayers);
        if (from == 0)
            c.emitter->start();  // the whole print before it: the very state
        else
            c.emitter->warm_up();
        if (c.flipped) c.emitter->flip_next_order();
        for (int i = from; i < c.first; ++i) c.emitter->layer(load(i));
        c.emitter->begin_chunk(c.body.file);
    }
    c.entry = c.emitter->carry();
    for (int i = c.first; i < c.end; ++i) c.emitter->layer(load(i));
    c.keep_figures();
}

// Every task on up to `threads` threads; the CPU time they took, summed.
int64_t GcodeWriter::Impl::write_chunks(const std::vector<Chunk*>& tasks) const {
    std::atomic<int64_t> parallel_ns = 0;
    auto timed = [&](Chunk& c) {
        const int64_t chunk_start_ns = thread_cpu_ns();
        write_chunk(c);
        parallel_ns += thread_cpu_ns() - chunk_start_ns;
    };
    if (tasks.size() == 1) {
        timed(*tasks[0]);
    } else {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
        tbb::task_arena arena(threads);
        arena.execute([&] {
            tbb::parallel_for(size_t(0), tasks.size(), [&](size_t t) { timed(*tasks[t]); });
        });
    }
    return parallel_ns.load();
}

// Chunk k after the one before it: its other guess if that one started from where the chunk
// before ended, or else, if its own guess did not either, written again by the emitter of the
// one before, which goes on from the very state.
void GcodeWriter::Impl::reconcile(std::vector<Chunk>& chunks, size_t k) {
    Chunk& c = chunks[k];
    const std::optional<Emitter::Carry> before =
        k > 0 ? std::optional(chunks[k - 1].emitter->carry()) : std::nullopt;
    if (before && c.other && !(*before == c.entry) && *before == c.other->entry) {
        c.take(*c.other);
        ++chunk_count.second_guesses;
    }
    c.other.reset();
    if (before && !(*before == c.entry)) {
        ++chunk_count.written_again;
        c.emitter = std::move(chunks[k - 1].emitter);
        if (std::fflush(c.body.file) != 0 || ftruncate(fileno(c.body.file), 0) != 0 ||
            std::fseek(c.body.file, 0, SEEK_SET) != 0)
            io_error(std::strerror(errno), output_path);
        c.emitter->begin_chunk(c.body.file);
        for (int i = c.first; i < c.end; ++i) c.emitter->layer(load(i));
        c.keep_figures();
    }
}

// The chunks in order, each reconciled with the one before; the last one writes the end, on
// the totals of every layer.
ChunkSums GcodeWriter::Impl::sum_chunks(std::vector<Chunk>& chunks) {
    ChunkSums sums;
    for (size_t k = 0; k < chunks.size(); ++k) {
        reconcile(chunks, k);
        Chunk& c = chunks[k];
        sums.add_sections(c, 0);
        if (k + 1 == chunks.size()) {
            // The end's time and figures close the totals (the emitter adds the end's section
            // as the loop above does, and derives the filament and the estimate from the sum).
            c.emitter->adopt_totals(sums.time, sums.stealth, sums.totals);
            c.emitter->end();
            const size_t own = c.sections.size();
            c.keep_figures();
            sums.add_sections(c, own);
            sums.totals = c.emitter->stats();
        }
        sums.add_extent(c);
        if (std::fflush(c.body.file) != 0 || std::ferror(c.body.file))
            io_error(std::strerror(errno), output_path);
        sums.rebase_marks(c, static_cast<long long>(ftello(c.body.file)));
    }
    return sums;
}

// The file: the header stating the figures, the bodies with their M73 lines, the trailer;
// committed now or held for the run's other outputs.
void GcodeWriter::Impl::assemble(std::vector<Chunk>& chunks,
                                 const std::vector<std::string>& header_comments,
                                 const ChunkSums& sums) {
    const PrintStats& s = sums.totals;
    auto file = std::make_unique<AtomicFile>(output_path);
    std::FILE* out = file->stream();
    Emitter text(settings, off_x, off_y, out, output_path);
    text.comment_block(head(header_comments, s, sums.bounds, sums.object_bounds));
    text.flush_all();
    std::vector<std::FILE*> bodies;
    for (Chunk& c : chunks) {
        if (std::fseek(c.body.file, 0, SEEK_SET) != 0) io_error(std::strerror(errno), output_path);
        bodies.push_back(c.body.file);
    }
    copy_with_progress(bodies, out, sums.marks, s.estimated_print_time_s, output_path,
                       settings.silent_mode != 0 ? s.estimated_stealth_time_s : -1);
    chunks.clear();
    text.comment_block(tail(s));
    text.flush_all();
    file->close();
    if (group) {
        written = file->temporary();
        group->hold(std::move(file));
    } else {
        file->commit();
        written = output_path;
    }
}

PrintStats GcodeWriter::finish(const std::vector<std::string>& header_comments) {
    std::lock_guard lock(impl_->mutex);
    Impl& m = *impl_;
    if (m.finished) throw std::logic_error("GcodeWriter::finish called twice");
    if (std::fflush(m.spill) != 0) io_error(std::strerror(errno), m.output_path);
    const int64_t start_ns = thread_cpu_ns();

    // The body in chunks, each measured as it is written.
    const int count =
        m.threads <= 1 ? 1 : std::clamp(m.layer_count / kMinChunkLayers, 1, 4 * m.threads);
    std::vector<Chunk> chunks(static_cast<size_t>(count));
    m.chunk_count.chunks = count;
    const std::vector<Chunk*> tasks = m.open_chunks(chunks);
    const int64_t parallel_start_ns = thread_cpu_ns();
    const int64_t parallel_ns = m.write_chunks(tasks);
    const int64_t parallel_end_ns = thread_cpu_ns();
    const ChunkSums sums = m.sum_chunks(chunks);
    refuse_beyond_machine(m.settings, sums.bounds);
    m.assemble(chunks, header_comments, sums);

    m.finished = true;
    std::fclose(m.spill);
    m.spill = nullptr;
    m.chunk_count.parallel_cpu_s = double(parallel_ns) * 1e-9;
    m.chunk_count.serial_cpu_s =
        double(parallel_start_ns - start_ns + thread_cpu_ns() - parallel_end_ns) * 1e-9;
    return sums.totals;
}

}  // namespace carve

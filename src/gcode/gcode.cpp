// G-code assembly: spill layers as they come (top down), write them bottom up at the end.
//
// Layers are spilled in a compact binary form (zig-zag varint deltas) to an unlinked temporary
// file next to the output, so nothing is left behind even if the process dies. finish() runs the
// emitter once over the spilled layers, writing the body to a second unlinked file while it
// measures (time, material, bounds); then the header stating those figures, the body and the
// trailer go to a temporary name that is renamed onto the output when complete. The figures
// come from the very moves written, so the header cannot disagree with the body. (A measuring
// pass before the writing pass did the same in twice the time, all of it after the last layer,
// when nothing else runs.)
#include "gcode/gcode.hpp"

#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <memory>
#include <mutex>
#include <stdexcept>

#include "base/atomic_file.hpp"
#include "base/error.hpp"
#include "base/stage_timer.hpp"
#include "gcode/emitter.hpp"
#include "gcode/header.hpp"
#include "gcode/labels.hpp"
#include "gcode/progress.hpp"
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

}  // namespace

struct GcodeWriter::Impl {
    std::string output_path;
    std::string written;  // where the complete file is (written_path())
    Settings settings;
    Coord off_x = 0, off_y = 0;
    int layer_count = 0;
    std::FILE* spill = nullptr;
    long long spill_end = 0;
    std::vector<long long> offsets, sizes;
    OutputGroup* group = nullptr;         // commit held back until the run's other outputs are done
    std::string object = "object";        // the object's label
    std::vector<ObjectLabel> objects;     // several objects, or none
    std::vector<std::string> thumbnails;  // the header's thumbnail blocks
    bool finished = false;
    std::mutex mutex;

    LayerToolpaths load(int index) {
        if (offsets[index] < 0) {
            LayerToolpaths empty;
            empty.index = index;
            empty.z = (index + 1) * settings.layer_height;
            return empty;
        }
        std::string blob(static_cast<size_t>(sizes[index]), '\0');
        if (fseeko(spill, offsets[index], SEEK_SET) != 0 ||
            std::fread(blob.data(), 1, blob.size(), spill) != blob.size())
            throw std::runtime_error("carve: cannot read back the layer spill file");
        return decode_layer(blob);
    }

    void run(Emitter& emitter) {
        emitter.start();
        for (int i = 0; i < layer_count; ++i) emitter.layer(load(i));
        emitter.end();
    }

    // The comment lines before the body, in PrusaSlicer's order: who made the file first
    // (hosts look there), the thumbnails, then Cura's summary lines and carve's own; the
    // figures and the configuration close the file (tail()), where Moonraker's PrusaSlicer
    // parser reads them.
    std::vector<std::string> head(const std::vector<std::string>& comments, const PrintStats& s,
                                  const Bounds& b, const std::vector<Bounds>& each) const {
        std::vector<std::string> lines{generated_by_line(), ";"};
        lines.insert(lines.end(), thumbnails.begin(), thumbnails.end());
        for (const std::string& c : comments) lines.push_back(c.rfind(';', 0) == 0 ? c : "; " + c);
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
            for (const std::string& l :
                 object_definition(settings, object, b.min_x, b.min_y, b.max_x, b.max_y))
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
    m.layer_count = std::max(0, layer_count);
    m.offsets.assign(m.layer_count, -1);
    m.sizes.assign(m.layer_count, 0);
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
    if (layer.index < 0 || layer.index >= m.layer_count)
        throw std::out_of_range("GcodeWriter::add_layer: layer index out of range");
    if (fseeko(m.spill, m.spill_end, SEEK_SET) != 0 ||
        std::fwrite(blob.data(), 1, blob.size(), m.spill) != blob.size())
        io_error(std::strerror(errno), m.output_path + " (temporary layer file)");
    m.offsets[layer.index] = m.spill_end;
    m.sizes[layer.index] = static_cast<long long>(blob.size());
    m.spill_end += static_cast<long long>(blob.size());
}

PrintStats GcodeWriter::finish(const std::vector<std::string>& header_comments) {
    std::lock_guard lock(impl_->mutex);
    Impl& m = *impl_;
    if (m.finished) throw std::logic_error("GcodeWriter::finish called twice");
    if (std::fflush(m.spill) != 0) io_error(std::strerror(errno), m.output_path);

    // The body, measured as it is written.
    std::FILE* body = unlinked_file(m.output_path, ".body-XXXXXX");
    std::FILE* out = nullptr;
    try {
        std::setvbuf(body, nullptr, _IOFBF, 1 << 16);
        Emitter writer(m.settings, m.off_x, m.off_y, body, m.output_path, m.object);
        if (!m.objects.empty()) writer.set_objects(m.objects);
        m.run(writer);
        writer.flush_all();
        if (std::fflush(body) != 0 || std::ferror(body) || std::fseek(body, 0, SEEK_SET) != 0)
            io_error(std::strerror(errno), m.output_path);
        const PrintStats s = writer.stats();
        const Bounds& b = writer.bounds();

        auto file = std::make_unique<AtomicFile>(m.output_path);
        out = file->stream();
        Emitter text(m.settings, m.off_x, m.off_y, out, m.output_path);
        text.comment_block(m.head(header_comments, s, b, writer.object_bounds()));
        text.flush_all();
        copy_with_progress(body, out, writer.progress_marks(), s.estimated_print_time_s,
                           m.output_path);
        std::fclose(body);
        body = nullptr;
        text.comment_block(m.tail(s));
        text.flush_all();
        const PrintStats result = s;
        out = nullptr;
        file->close();
        if (m.group) {
            m.written = file->temporary();
            m.group->hold(std::move(file));
        } else {
            file->commit();
            m.written = m.output_path;
        }
        m.finished = true;
        std::fclose(m.spill);
        m.spill = nullptr;
        return result;
    } catch (...) {
        if (body) std::fclose(body);
        throw;  // the AtomicFile removes its temporary
    }
}

}  // namespace carve

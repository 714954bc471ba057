// The emitter (private to the G-code stage): turns layers into G-code text and measures, from
// the very moves it writes, the figures the header states (time, material, bounds) and where
// the M73 lines go. GcodeWriter (gcode.cpp) runs it once over the spilled layers.
//
// Its work is in two files: emitter.cpp the programme of the file (start, layers with
// cooling's second pass, end) and the machine's state (fan, progress, text out), and
// emitter_moves.cpp the moves (travels with combing, retraction and wipe, extrusion, arcs, Z).
// The small text writers every move calls stay inline here.
#pragma once

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "config/settings.hpp"
#include "gcode/arcs.hpp"
#include "gcode/gcode.hpp"
#include "gcode/motion.hpp"
#include "gcode/progress.hpp"
#include "toolpath/comb.hpp"
#include "toolpath/toolpath.hpp"

namespace carve {

// Throws OutputError: "cannot write PATH: WHAT".
[[noreturn]] void io_error(const std::string& what, const std::string& path);

// What the printed moves cover, mm (the layers' Z, before --z-offset).
struct Bounds {
    double min_x = std::numeric_limits<double>::max(), min_y = min_x, min_z = min_x;
    double max_x = std::numeric_limits<double>::lowest(), max_y = max_x, max_z = max_x;
    // The highest Z any move writes, --z-offset included (a travel's lift, a custom G-code's
    // move), and what wrote it: the printer's height bounds these too (issue #52).
    double max_move_z = std::numeric_limits<double>::lowest();
    const char* max_move_what = "";
    bool empty() const { return min_x > max_x; }
    void moved_to(double z, const char* what) {
        if (z > max_move_z) max_move_z = z, max_move_what = what;
    }
};

// Turns layers into G-code text (or, without a file, only measures what it would print).
class Emitter {
  public:
    Emitter(const Settings& st, Coord off_x, Coord off_y, std::FILE* out, std::string path,
            std::string object = "object");

    void start();
    void layer(const LayerToolpaths& layer);
    void end();

    void comment_block(const std::vector<std::string>& lines) {
        for (const std::string& l : lines) line(l);
    }

    void flush_all() { flush(true); }
    // Flushes and gives back the text buffer's memory (it grows to kFlushBytes): a chunk's
    // emitter waits, written, until the chunks are put together.
    void release_text() {
        flush(true);
        fmt::memory_buffer empty;
        buf_ = std::move(empty);
    }
    // The totals, complete after end().
    const PrintStats& stats() const { return run_stats_; }
    const std::vector<ProgressMark>& progress_marks() const { return marks_; }
    const Bounds& bounds() const { return bounds_; }
    // Several objects: each extrusion labelled as its own object's (the single object's label
    // otherwise); their extents as written.
    void set_objects(std::vector<ObjectLabel> objects);
    const std::vector<Bounds>& object_bounds() const { return object_bounds_; }

    // --- chunks. GcodeWriter::finish writes the layers in chunks on several threads, each
    // chunk's emitter starting from the state its warm-up (the layers just before the chunk,
    // written to nowhere) leaves, and checks afterwards that this state is the one the chunk
    // before ended in (else that chunk's emitter writes the chunk again). Every layer starts
    // from a state its text depends on (Carry) and adds to the totals (a Section): E is reset
    // at each layer's end and the motion planner's time taken, so that neither depends on the
    // length of the print before. The totals are the sections summed in order, by the emitter
    // as it goes or by the writer over the chunks: the same bits either way.
    struct Section {
        PrintStats stats;
        double time_s = 0, stealth_time_s = 0;
    };
    // What a layer's text depends on from the layers before it: all the emitter carries from
    // one layer to the next, and nothing else does (the rest is the open layer's scratch, the
    // settings' constants, or the figures a chunk adds up). Held as one member, carry_, so that
    // a chunk's check of its warm-up and cooling's second pass compare and restore all of it.
    // The defaults are the print's start.
    struct Carry {
        Point pos{0, 0};  // output coordinates, um; the start G-code is assumed to home
        Coord z = -1;     // unknown until the first Z move
        Coord layer_z = 0;
        // The layer being written, numbered as Settings numbers them (a raft's < 0).
        int layer = 0;
        double e_mm = 0;        // filament fed for extrusion so far (retractions excluded)
        long long e_units = 0;  // the firmware's E position, in 10^-5 mm
        long long feed = -1;    // the F in force
        bool retracted = false;
        bool first_travel = true;  // nothing printed yet
        int fan = -1;
        bool type_known = false;  // the ;TYPE: in force is type
        Feature type = Feature::OuterWall;
        double width = -1;                   // the ;WIDTH: in force
        double accel = -1;                   // the M204 S in force (switches_acceleration)
        double wipe_length = 0;              // mm, of wipe_path
        std::vector<char> objects_labelled;  // M486 A named it
        MotionPlanner planner;
        Path wipe_path;  // output coordinates, from the nozzle backwards
        bool operator==(const Carry&) const = default;
    };
    const Carry& carry() const { return carry_; }
    // Starts the next layer from `c`, as though this emitter had written the layers that left
    // it: gcode_test's check that Carry holds every state a layer's text depends on.
    void resume(const Carry& c) { carry_ = c; }
    // A chunk's emitter before its warm-up layers: it writes nowhere, its first travel is not
    // the print's first, and the objects are already named (on the print's first layer).
    void warm_up();
    // The next layer of several islands is printed in the other order than the one its entry
    // picks: the warm-up that guesses the other of the two ways a run of such layers goes.
    void flip_next_order() { flip_ = true; }
    // The chunk's own text starts here, in `out`; what the warm-up measured is forgotten.
    void begin_chunk(std::FILE* out);
    // Before end(): the totals of the sections before this emitter's next one, from all chunks.
    void adopt_totals(double time_s, double stealth_time_s, const PrintStats& stats);
    const std::vector<Section>& sections() const { return sections_; }
    size_t custom_bytes() const { return custom_bytes_; }
    // Throws InputError when the profile's custom G-code added more than its bound in all.
    static void check_custom_bytes(size_t bytes);
    static void add_stats(PrintStats& to, const PrintStats& s);

  private:
    static constexpr double kZSpeed = 10.0;  // mm/s for layer changes and z-hops
    // mm a pause lifts the nozzle by (within the printer's height), clear of the part and of
    // what oozes onto it, before the command's own parking, if it has one (a bare PAUSE has
    // none).
    static constexpr double kPauseLift = 5.0;
    static constexpr long long kEScale = 100000;  // E is written with 5 decimals
    // Text buffered before each fwrite, checked at each layer's end. Small enough to stay in
    // cache: a 1 MB buffer cost each chunk's emitter 256 fresh pages, at some 10 us a page
    // fault on a virtual machine, for no fewer bytes written.
    static constexpr size_t kFlushBytes = 1 << 16;
    static constexpr Coord kMaxCoord = 100'000'000;  // 100 m in um: no printer's bed, a guard only

    // The last guard before a number reaches the printer: settings are validated where they
    // are read, so a value failing here is carve's own bug, reported instead of written (a NaN
    // would come out as E-92233720368547.75808 or F-9223372036854775808).
    static void guard(bool ok, const char* word) {
        if (!ok)
            throw std::runtime_error(std::string("G-code emitter: refusing a non-finite or "
                                                 "out-of-range ") +
                                     word + " word");
    }

    // --- text output (emitter.cpp, but for the writers every move calls).
    void put(std::string_view s) { buf_.append(s.data(), s.data() + s.size()); }
    void line(std::string_view s) {
        put(s);
        buf_.push_back('\n');
    }
    void raw(const std::string& text);
    // The Z words of custom G-code's G0/G1 moves (G90/G91 followed), into bounds_ as `what`'s.
    void scan_custom_z(const std::string& text, const char* what);
    // A profile's filament or layer-change G-code, expanded for the layer being written. A
    // "G92 E0" in it resets the firmware's E, as PrusaSlicer assumes.
    void custom(const std::string& text);
    // A value in units of 10^-decimals (decimals >= 1), written with exactly that many
    // decimals. By hand: every coordinate of the file passes here, and fmt's general path (a
    // format string parsed per call) was most of the time spent writing G-code.
    void fixed(long long v, int decimals) {
        if (v < 0) {
            buf_.push_back('-');
            v = -v;
        }
        char digits[24];  // least significant first, at least decimals + 1 of them
        int n = 0;
        do {
            digits[n++] = static_cast<char>('0' + v % 10);
            v /= 10;
        } while (v > 0 || n <= decimals);
        for (int i = n - 1; i >= 0; --i) {
            if (i == decimals - 1) buf_.push_back('.');
            buf_.push_back(digits[i]);
        }
    }
    void flush(bool force);

    // --- machine state changes (emitter.cpp).
    void set_fan(int speed);
    static int fan_byte(int percent) {
        return static_cast<int>(std::lround(std::clamp(percent, 0, 100) * 2.55));
    }
    // An M73 goes here, `local_s` into the open section (-1: at the end, the total).
    void mark_progress(double local_s, double stealth_local_s);
    // Ends the open section: its figures and time go to the totals.
    void close_section();
    // G92 E0 (with absolute E): the next layer's E does not depend on the filament before it.
    void reset_e();

    // --- moves (emitter_moves.cpp).
    void feed(double mm_per_s);
    void e_word(long long target);
    void move_filament(long long target);
    bool can_retract() const { return st_.firmware_retraction || retract_units_ > 0; }
    void retract();
    void wipe();
    void unretract();
    // `what` names the move when the printer's height refuses it (a lift or a layer change).
    void move_z(Coord z, const char* what = nullptr);
    void retract_dwell();
    // --pause-at's park, command and return.
    void pause();
    void travel_to(const Point& p, const Path& via, TravelKind kind);
    void travel_move(const Point& p);
    TravelPlan plan_layer_entry(const Point& target_model);
    TravelPlan find_layer_entry(const Point& from, const Point& target_model);
    // Whether the layer's islands should be printed last to first: its last island is where
    // the nozzle can enter without leaving the part, or nearer.
    bool enter_reversed(const LayerToolpaths& layer);
    double speed_of(Feature f) const;
    // The layer being written's thickness, mm (the first layer's may differ).
    double thickness() const { return st_.layer_thickness_mm(carry_.layer); }
    void extrude(const Extrusion& ex, const Travel& travel);
    void printed(const Point& q, double len, double e_per_mm, Feature feature);
    void arc_to(const std::vector<Point>& pts, size_t first, const Arc& arc, double speed,
                double e_per_mm, Feature feature);
    template <class Shift>
    void remember_for_wipe(const Extrusion& ex, Shift shifted);
    void use_acceleration(double a);

    // --- cooling (emitter.cpp).
    // Everything a layer's paths change, to write the layer again slower: the state the next
    // layer starts from, and the open section's text and figures.
    struct Snapshot {
        size_t text = 0;
        Carry carry;
        std::vector<Bounds> object_bounds;
        PrintStats stats;
        Bounds bounds;
    };
    Snapshot save() const;
    void restore(const Snapshot& k);
    void print_layer_cooled(const LayerToolpaths& layer);
    void print_paths(const LayerToolpaths& layer);
    int object_of(const Point& p) const;

    const Settings& st_;
    Coord off_x_, off_y_;
    std::FILE* out_;
    std::string path_;
    std::vector<ProgressMark> marks_;  // where the M73 lines go
    long long written_ = 0;            // bytes of text flushed to out_
    double speed_factor_ = 1;          // cooling's slowdown of the layer being written
    int layer_fan_ = 0;                // percent, for the layer's ordinary extrusions
    // The print's and the travel's accelerations as written and planned (limits.hpp).
    double print_accel_ = 0, travel_accel_ = 0;
    // The objects on the bed: one (the model, named at construction) or what set_objects gave.
    std::vector<ObjectLabel> objects_;
    std::vector<Bounds> object_bounds_;
    int object_ = -1;  // index in objects_ of what is being printed
    fmt::memory_buffer buf_;
    double filament_area_ = 1;
    long long retract_units_ = 0;
    Coord z_offset_ = 0;  // --z-offset, added to every Z written
    Carry carry_;         // what the next layer starts from (see Carry)

    // Its number in the print, from 0: what ;LAYER:, [layer_num] and the first-layer rules count.
    int print_layer() const { return carry_.layer - st_.first_print_layer(); }
    // The expanded custom G-code written so far: 64 MB is some 60x what a 4 MB layer_gcode
    // could sensibly add, far beyond any real profile's few kB per layer.
    static constexpr size_t kMaxCustomBytes = size_t(64) << 20;
    size_t custom_bytes_ = 0;
    std::vector<Point> path_points_;  // the path being printed, shifted, reused
    PrintStats stats_;                // of the open section
    PrintStats run_stats_;            // of the closed sections, summed in order
    double time_base_ = 0;            // their time, summed in order
    double stealth_base_ = 0;         // and in the stealth mode
    std::vector<Section> sections_;
    bool flip_ = false;  // flip_next_order()
    Bounds bounds_;
    const Paths* layer_comb_ = nullptr;  // the comb region of the layer being written
    std::unique_ptr<Comber> comber_;     // built from it on first use
    const Paths* layer_thin_ = nullptr;  // and its region inside the outer wall's centreline
    std::unique_ptr<Comber> thin_;       // built from that if the comb region fails
    // plan_layer_entry's last two answers on this layer: the entry's order is chosen by
    // planning both candidates, and the one chosen is then planned again to be travelled.
    struct LayerEntry {
        Point from, to;
        TravelPlan plan;
    };
    std::vector<LayerEntry> last_entries_;
};

}  // namespace carve

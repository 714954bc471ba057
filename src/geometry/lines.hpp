// Operations on open polylines as a printer lays them: lines that must not print twice.
#pragma once

#include <memory>

#include "geometry/types.hpp"

namespace carve {

// Each line in turn, less its parts nearer than `radius` to the lines kept before it: what
// is left prints no filament where an earlier line already lies. Lines keep their order; a line
// cut in the middle gives two, each ending `radius` from the line that cut it, so that with a
// radius under the line width the two still fuse with it. Pieces left at a line's free ends
// shorter than `min_end` are dropped (a stub beside another line holds nothing); pieces between
// two cuts are kept whatever their length, as they may be what joins two lines.
Paths trim_overlaps(const Paths& lines, Coord radius, Coord min_end);

// The same, a line at a time: add() returns what is left of a line after the lines added
// before it (lines of several kinds trimmed against each other, each kept with its kind).
class LineSet {
  public:
    LineSet(Coord radius, Coord min_end);
    ~LineSet();
    Paths add(const Path& line);
    // A line kept whole, that later lines are trimmed against.
    void keep(const Path& line);

  private:
    struct Grid;
    Coord radius_, min_end_;
    std::unique_ptr<Grid> kept_;
};

// Where a family of parallel lines runs inside a region. The lines are {p : n.p = s} for each s
// in `offsets` (ascending), with d = (dx, dy) a unit direction and n = (-dy, dx) its normal; each
// gets the intervals of d.p it spends inside (even-odd), in order. Edge by edge, so that many
// lines over a region of many edges cost the edges and the crossings, not their product.
struct Chord {
    double from = 0, to = 0;  // along d
};
std::vector<std::vector<Chord>> chords(const Paths& region, double dx, double dy,
                                       const std::vector<double>& offsets);

// The point at `along` on the line of offset `s` (the frame of chords()).
Point chord_point(double dx, double dy, double s, double along);

}  // namespace carve

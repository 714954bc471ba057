// M73 progress for printer screens and hosts (Prusa and Marlin firmware, Mainsail, Fluidd):
// "M73 P<percent done> R<minutes remaining>". The body is written before its total time is
// known, so the emitter only notes where each M73 goes (a byte offset in the body) and the
// estimate's time there; the lines are put in while the body is copied behind the header.
#pragma once

#include <cstdio>
#include <string>
#include <vector>

namespace carve {

struct ProgressMark {
    long long offset = 0;  // byte offset in the body, before which the line goes
    double elapsed_s = 0;  // estimated time from the start of the body to there
    // Where elapsed_s comes from: the time into the emitter's section (the start, a layer, the
    // end) that holds the mark, added to the sections' times before it.
    size_t section = 0;
    double local_s = 0;
    // The same in the stealth mode (--silent-mode): M73 Q/S.
    double stealth_elapsed_s = 0, stealth_local_s = 0;
};

// "M73 P12 R34": the percentage is rounded down (100 only at the end), so that it never runs
// ahead of the print; the minutes left are rounded to the nearest.
// A time into the print and the print's total, in one mode.
struct ProgressTime {
    double elapsed_s = 0, total_s = 0;
};

// With `stealth`, also "M73 Q12 S34", the figures a Prusa printer shows in its stealth mode,
// from the stealth mode's own times (as PrusaSlicer times that mode with its silent limits).
std::string m73_line(ProgressTime normal, const ProgressTime* stealth = nullptr);

// Copies the `bodies` one after the other (each from its current position to its end) to
// `out`, with the M73 line of each mark put before the byte it names, counted through the
// bodies as one; marks must be in increasing order. Throws OutputError naming `path` on a
// failed write.
// With `stealth_total_s` >= 0, the lines carry the stealth figures too.
void copy_with_progress(const std::vector<std::FILE*>& bodies, std::FILE* out,
                        const std::vector<ProgressMark>& marks, double total_s,
                        const std::string& path, double stealth_total_s = -1);

}  // namespace carve

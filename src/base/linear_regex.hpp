// A regular expression matcher in linear time: the pattern is compiled to a Thompson NFA and
// simulated over the text one character at a time (a set of states, never backtracking), so
// the time is O(pattern x text) whatever the pattern. std::regex backtracks: a 30-character
// pattern in a profile condition ran for minutes, and its recursion overflowed the stack on
// PrusaSlicer's own `printer_notes=~/.*PRINTER_VENDOR_PRUSA3D.*/` once the notes pass ~16 kB.
//
// The subset PrusaSlicer profiles use: literals, '.', character classes ([a-z0-9_], [^...]),
// escapes (\d \w \s \D \W \S and escaped punctuation), grouping (...) and (?:...), alternation
// '|', repetition * + ? {n} {n,} {n,m}, anchors ^ $. No back-references or look-around (they
// cannot be matched in linear time). Patterns are bounded: 4096 characters, 64 levels of
// nesting, 20,000 compiled instructions; beyond that, or on a syntax error, the constructor
// throws std::invalid_argument saying why.
// Bottom layer: depends on nothing else of carve.
#pragma once

#include <bitset>
#include <string_view>
#include <vector>

namespace carve {

class LinearRegex {
  public:
    explicit LinearRegex(std::string_view pattern);
    // Does the whole of `text` match (std::regex_match's meaning, as PrusaSlicer's =~)?
    bool full_match(std::string_view text) const;

    struct Inst {
        enum Op : unsigned char { Set, Split, Jmp, Bol, Eol, Match } op;
        int x = 0, y = 0;  // jump targets (Split: both, Jmp: x), or the set's index (Set: x)
    };

  private:
    std::vector<Inst> prog_;
    std::vector<std::bitset<256>> sets_;
};

}  // namespace carve

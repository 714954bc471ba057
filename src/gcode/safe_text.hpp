// Text that comes from outside carve (file and object names, profile names and values, a line
// of custom G-code turned into a comment) and is written into the G-code. A firmware ends a
// line at a line feed or a carriage return, and some read a NUL as the end of the file, so a
// name holding one of them could end the comment it is in and put a command of its author's on
// the printer (`carve slice $'evil\nM104 S300\n.stl'`, issue #38). Every such string goes
// through these functions; nothing else in the gcode stage writes outside text.
#pragma once

#include <string>
#include <string_view>

namespace carve {

// For a comment: every control character (below 0x20 and 0x7f) but the tab is written as an
// escape that stays readable and on the line ("\n", "\r", "\0", else "\x1b"); other bytes,
// UTF-8 included, are kept.
std::string comment_text(std::string_view text);

// For a name inside a command (M486 A, EXCLUDE_OBJECT_DEFINE NAME=, which a space or ';'
// would cut): letters, digits, '_', '-' and '.', every other byte turned into '_'; "object" if
// the name is empty.
std::string label_text(std::string_view name);

}  // namespace carve

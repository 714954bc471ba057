// Before a run writes anything: refuses an output that is one of the run's inputs or another of
// its outputs (the real files are compared: device and inode when they exist, the canonical path
// when they do not, so "dir/../dir/./M.stl" is M.stl), and an output that exists but is not a
// regular file (a device such as /dev/null, a FIFO) or, for a folder output, not a folder.
// Bottom layer: depends on nothing else of carve.
#pragma once

#include <string>
#include <vector>

namespace carve {

struct NamedPath {
    std::string path;  // as the user spelled it; empty = not used
    std::string what;  // "the model", "--stats", ...
    bool folder = false;
};

// Throws OutputError naming both paths.
void check_output_paths(const std::vector<NamedPath>& inputs,
                        const std::vector<NamedPath>& outputs);

}  // namespace carve

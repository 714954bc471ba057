// Object labels, so that a host or printer can cancel one object: "; printing object NAME" and
// "; stop printing object NAME" (PrusaSlicer's comments, which Moonraker and OctoPrint's
// Cancelobject read) around each object's part of each layer, with Klipper's
// EXCLUDE_OBJECT_DEFINE / _START / _END for the Klipper flavour and M486 (Marlin, Prusa and
// RepRap firmware) for the others.
#pragma once

#include <string>
#include <vector>

#include "config/settings.hpp"

namespace carve {

// One of several objects on the bed (--copies): its label and where it lies, model
// coordinates in mm; an extrusion belongs to the object whose box holds its first point.
struct ObjectLabel {
    std::string name;
    double min_x = 0, min_y = 0, max_x = 0, max_y = 0;
};

// A name every host accepts: letters, digits, '_', '-' and '.', the rest turned into '_'
// ("my part (2).stl" -> "my_part__2_"); "object" if nothing is left.
std::string object_label(const std::string& model_path);

// The header's definition of an object: Klipper's EXCLUDE_OBJECT_DEFINE with the object's
// centre and outline (its extrusion's bounding rectangle), or M486 T with the object count
// (written once, for the first object).
std::vector<std::string> object_definition(const Settings& s, const std::string& name, double min_x,
                                           double min_y, double max_x, double max_y, int count = 1);

// The lines that open and close the object's part of a layer; `first` names it for M486.
std::vector<std::string> object_start(const Settings& s, const std::string& name, int id,
                                      bool first);
std::vector<std::string> object_end(const Settings& s, const std::string& name);

}  // namespace carve

// PNG encoding, for the pictures both outputs for machines write: the G-code thumbnails a host
// shows, and the images of a resin slice stack. One encoder, so libpng's error handling (a
// longjmp) is written once.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>

namespace carve {

struct PngFormat {
    int channels = 4;  // 1: grey, 4: RGBA; 8 bits each
    int compression_level = 9;
    // Binary images of long runs (resin layers): the Sub filter turns runs into zeros that
    // zlib's run-length strategy finds at a fraction of the default strategy's time.
    bool run_length = false;
};

// Writes width x height pixels (rows top down, channels bytes each, no padding) to an open
// file. False when libpng fails (a full disk shows up here), with libpng's words and the
// system's reason in `why`; nothing is printed, the caller names the file.
bool write_png(FILE* file, int width, int height, const uint8_t* pixels, const PngFormat& format,
               std::string* why = nullptr);

}  // namespace carve

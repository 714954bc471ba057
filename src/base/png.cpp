// PNG encoding through libpng (png.hpp).
#include "base/png.hpp"

#include <png.h>
#include <zlib.h>

#include <cerrno>
#include <csetjmp>
#include <cstddef>
#include <cstring>

namespace carve {

namespace {

// libpng's own handlers print "libpng error: Write Error" on stderr (twice on a full disk) and
// say nothing of why: these keep its words and errno for the caller's one line instead.
void keep_error(png_structp png, png_const_charp message) {
    auto* why = static_cast<std::string*>(png_get_error_ptr(png));
    const int err = errno;
    if (why) {
        *why = message ? message : "libpng error";
        if (err != 0) (*why += ": ") += std::strerror(err);
    }
    png_longjmp(png, 1);
}
void ignore_warning(png_structp, png_const_charp) {}

}  // namespace

// libpng reports errors through longjmp; this function holds no C++ object that needs a
// destructor between setjmp and the calls that may jump (`why` is the caller's).
bool write_png(FILE* file, int width, int height, const uint8_t* pixels, const PngFormat& format,
               std::string* why) {
    if (format.channels != 1 && format.channels != 4) return false;
    errno = 0;
    png_structp png =
        png_create_write_struct(PNG_LIBPNG_VER_STRING, why, keep_error, ignore_warning);
    if (!png) return false;
    png_infop info = png_create_info_struct(png);
    if (!info) {
        png_destroy_write_struct(&png, nullptr);
        return false;
    }
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        return false;
    }
    png_init_io(png, file);
    if (format.run_length) {
        png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_SUB);
        png_set_compression_strategy(png, Z_RLE);
    }
    png_set_compression_level(png, format.compression_level);
    png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), 8,
                 format.channels == 1 ? PNG_COLOR_TYPE_GRAY : PNG_COLOR_TYPE_RGBA,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    const size_t stride = static_cast<size_t>(width) * static_cast<size_t>(format.channels);
    for (int row = 0; row < height; ++row)
        png_write_row(png, pixels + static_cast<size_t>(row) * stride);
    png_write_end(png, info);
    png_destroy_write_struct(&png, &info);
    return true;
}

}  // namespace carve

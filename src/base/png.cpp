// PNG encoding through libpng (png.hpp).
#include "base/png.hpp"

#include <png.h>
#include <zlib.h>

#include <csetjmp>
#include <cstddef>

namespace carve {

// libpng reports errors through longjmp; this function holds no C++ object that needs a
// destructor between setjmp and the calls that may jump.
bool write_png(FILE* file, int width, int height, const uint8_t* pixels, const PngFormat& format) {
    if (format.channels != 1 && format.channels != 4) return false;
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
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

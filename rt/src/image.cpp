// PNG writer (libpng) and the raw little-endian ID / t buffers.
#include "rt/image.hpp"
#include "base/error.hpp"
#include "base/write_file.hpp"

#include <fmt/format.h>
#include <png.h>

#include <bit>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <stdexcept>

namespace nesshi::rt {

namespace {
void write_words(const std::string& path, const std::uint32_t* words, std::size_t n) {
    std::string bytes(n * 4, '\0');
    for (std::size_t i = 0; i < n; ++i)
        for (int b = 0; b < 4; ++b) bytes[i * 4 + static_cast<std::size_t>(b)] = static_cast<char>(words[i] >> (8 * b));
    base::write_file(path, bytes);
}
} // namespace

void write_png(const std::string& path, const Image& img) {
    base::OutputFile f(path);
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    if (!png) throw std::runtime_error("libpng: cannot create write struct");
    png_infop info = png_create_info_struct(png);
    if (!info || setjmp(png_jmpbuf(png))) {
        const int err = std::ferror(f.get()) ? errno : 0; // libpng's "Write Error": the file's own error
        png_destroy_write_struct(&png, &info);
        if (err) throw base::WriteError(path, err);
        throw base::Error(base::SourceLoc(path), "PNG write failed");
    }
    png_init_io(png, f.get());
    png_set_IHDR(png, info, static_cast<png_uint_32>(img.width), static_cast<png_uint_32>(img.height), 8,
                 PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    for (int y = 0; y < img.height; ++y)
        png_write_row(png, img.rgb.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(img.width) * 3);
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    f.close(); // the last rows are written here, so a full disk shows here
}

void write_id_buffer(const std::string& path, const std::vector<std::int32_t>& ids) {
    std::vector<std::uint32_t> w(ids.size());
    for (std::size_t i = 0; i < ids.size(); ++i) w[i] = static_cast<std::uint32_t>(ids[i]);
    write_words(path, w.data(), w.size());
}

void write_t_buffer(const std::string& path, const std::vector<float>& ts) {
    std::vector<std::uint32_t> w(ts.size());
    for (std::size_t i = 0; i < ts.size(); ++i) w[i] = std::bit_cast<std::uint32_t>(ts[i]);
    write_words(path, w.data(), w.size());
}

} // namespace nesshi::rt

// Framebuffer and the output files: PNG image, eye-ray ID buffer, t-buffer.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace nesshi::rt {

struct Image {
    int width = 0, height = 0;
    std::vector<std::uint8_t> rgb; // row-major, top row first, 3 bytes per pixel
};

// Each throws std::runtime_error on an I/O failure.
void write_png(const std::string& path, const Image& img);
// Raw little-endian int32 / float32, no header, rows top first.
void write_id_buffer(const std::string& path, const std::vector<std::int32_t>& ids);
void write_t_buffer(const std::string& path, const std::vector<float>& ts);

} // namespace nesshi::rt

#include "machine/memory_report.hpp"

#include "iss/cache.hpp"
#include "kernels/abi.hpp"
#include "machine/machine.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace nesshi::machine {

namespace abi = kernels::abi;

MemoryReport memory_report(const rt::Grid& g, std::size_t shape_count) {
    const int* n = g.geom.n;
    MemoryReport m;
    for (int k = 0; k < 3; ++k) m.padded[k] = n[k] + 2;
    m.os_voxel_map = g.occupancy.size();
    m.os_padded_map = abi::os_padded_map_bytes(n[0], n[1], n[2]);
    m.os_below_map = abi::kOsOcc;
    m.os_used = abi::os_sram_bytes(n[0], n[1], n[2]);
    m.os_sram_fits = abi::os_sram_fits(n[0], n[1], n[2]);
    const std::size_t padded = m.os_padded_map; // one list per padded voxel
    m.ic_header = abi::kIcData - abi::kIcHeader;
    m.ic_offsets = abi::ic_table_bytes(padded);
    m.ic_lists = abi::ic_lists_bytes(padded, g.prims.size());
    m.ic_shapes = abi::ic_records_bytes(shape_count);
    m.ic_data_resident = abi::ic_data_fit_resident(shape_count, padded, g.prims.size());
    m.os_sram_bytes = abi::kOsOccLimit - abi::kOsGeom;
    m.ic_resident_bytes = abi::get("IC_RESIDENT_LIMIT") - abi::kIcHeader;
    m.ic_cache_bytes = iss::CacheGeometry{}.bytes;
    return m;
}

MemoryReport memory_report(const rt::Grid& g, std::size_t shape_count, const Options& mo) {
    MemoryReport m = memory_report(g, shape_count);
    m.ic_real_cache = mo.cache.enabled;
    if (mo.cache.enabled) m.ic_cache_bytes = mo.cache.bytes;
    m.ic_no_resident = !mo.resident;
    return m;
}

namespace {
std::string mib(std::size_t b) { return fmt::format("{:.3f} MiB", static_cast<double>(b) / (1024.0 * 1024.0)); }

nlohmann::json memory_json(const MemoryReport& m) {
    nlohmann::json j = {{"os_voxel_map_bytes", m.os_voxel_map},
            {"os_padded_map_bytes", m.os_padded_map},
            {"os_below_map_bytes", m.os_below_map},
            {"os_total_bytes", m.os_total()},
            {"os_sram_bytes", m.os_sram_bytes},
            {"os_fits", m.os_fits()},
            {"ic_header_bytes", m.ic_header},
            {"ic_offsets_bytes", m.ic_offsets},
            {"ic_lists_bytes", m.ic_lists},
            {"ic_shapes_bytes", m.ic_shapes},
            {"ic_total_bytes", m.ic_total()},
            {"ic_resident_bytes", m.ic_resident_bytes},
            {"ic_cache_bytes", m.ic_cache_bytes},
            {"ic_fits_resident", m.ic_resident_fits()}};
    if (m.ic_no_resident) j["ic_no_resident"] = true;
    return j;
}
} // namespace

std::string MemoryReport::text() const {
    std::string o;
    o += fmt::format("memory   OS SRAM: geometry + ray states {} B + padded voxel map {}x{}x{} {} B = {} of {} ({})\n",
                     os_below_map, padded[0], padded[1], padded[2], os_padded_map, mib(os_total()), mib(os_sram_bytes),
                     os_fits() ? "fits" : "DOES NOT FIT: use a coarser grid");
    o += fmt::format("         IC: header {} B + voxel table {} B + lists {} B + records {} B = {} against {} resident + {} "
                     "{}cache ({})\n",
                     ic_header, ic_offsets, ic_lists, ic_shapes, mib(ic_total()), mib(ic_resident_bytes),
                     mib(ic_cache_bytes), ic_real_cache ? "LRU " : "",
                     ic_no_resident       ? "--no-resident: all in global memory, behind the cache"
                     : ic_resident_fits() ? "fits resident"
                                          : "exceeds resident: the most-referenced records go there, the other records, "
                                            "the voxel table and the lists to global memory");
    return o;
}

std::string MemoryReport::json() const { return memory_json(*this).dump(2); }

nlohmann::json with_memory_report(nlohmann::json stats, const rt::Grid& g, std::size_t shape_count) {
    stats["grid"]["memory"] = memory_json(memory_report(g, shape_count));
    return stats;
}

nlohmann::json with_memory_report(nlohmann::json stats, const rt::Grid& g, std::size_t shape_count, const Options& mo) {
    stats["grid"]["memory"] = memory_json(memory_report(g, shape_count, mo));
    return stats;
}

} // namespace nesshi::machine

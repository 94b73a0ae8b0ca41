// The machine's memory layout for a grid: the OS SRAM (geometry, ray state table, padded voxel
// map) and the IC data (header, voxel table, lists, shape records) against the memories' sizes.
// It applies the capacity rules of kernels/abi.hpp that the machine applies too (os_sram_fits,
// ic_data_fit_resident): the report says "fits" exactly when the machine takes the grid, and
// "fits resident" exactly when it puts all IC data in resident memory.
//
//   const machine::MemoryReport m = machine::memory_report(prep.grid, prep.shapes.shapes.size());
//   fmt::print("{}", m.text());   if (!m.os_fits()) ...
#pragma once

#include "rt/grid.hpp"

#include <nlohmann/json_fwd.hpp>

#include <cstddef>
#include <string>

namespace nesshi::machine {

struct MemoryReport {
    int padded[3] = {2, 2, 2};      // the padded map's dimensions (n + 2 per axis)
    std::size_t os_voxel_map = 0;   // occupancy bytes, unpadded (nx ny nz)
    std::size_t os_padded_map = 0;  // the map as the OS holds it, with its frame: (nx+2)(ny+2)(nz+2)
    std::size_t os_below_map = 0;   // geometry and ray state table, below the map (OS_OCC)
    std::size_t os_used = 0;        // os_below_map + os_padded_map: the end of the map in OS SRAM
    bool os_sram_fits = false;      // kernels::abi::os_sram_fits
    std::size_t ic_header = 0;      // header and dispatch tables below IC_DATA
    std::size_t ic_offsets = 0;     // voxel table: a list address per padded voxel
    std::size_t ic_lists = 0;       // a word per reference, an END word per list, one read-ahead word
    std::size_t ic_shapes = 0;      // the END record and the shape records, 80 B each
    bool ic_data_resident = false;  // kernels::abi::ic_data_fit_resident
    std::size_t os_sram_bytes = 0;     // the OS SRAM (ABI: OS_OCC_LIMIT, the presets' "sram")
    std::size_t ic_resident_bytes = 0; // IC resident memory (ABI, the presets' "resident")
    std::size_t ic_cache_bytes = 0;    // the IC cache's size: --cache-size, else the default (iss::CacheGeometry)
    bool ic_real_cache = false;        // --cache: an LRU cache of that size (else the ideal one, 100% hits)
    bool ic_no_resident = false;       // --no-resident: every IC datum in global memory, behind the cache

    std::size_t os_total() const { return os_used; }
    std::size_t ic_total() const { return ic_header + ic_offsets + ic_lists + ic_shapes; }
    bool os_fits() const { return os_sram_fits; }
    bool ic_resident_fits() const { return ic_data_resident; }

    std::string text() const; // the two "memory" lines of `nesshi scene info`
    std::string json() const; // the stats JSON's grid.memory object
};

struct Options;

// With `mo`: the report of that machine (its cache size, resident memory used or not); without,
// of the default machine (the ideal 1 MiB cache, resident memory used).
MemoryReport memory_report(const rt::Grid& g, std::size_t shape_count);
MemoryReport memory_report(const rt::Grid& g, std::size_t shape_count, const Options& mo);

// A render's stats JSON (rt::stats_json) with the machine's memory report as grid.memory.
// ic_no_resident appears only when true (the default report's keys do not change).
nlohmann::json with_memory_report(nlohmann::json stats, const rt::Grid& g, std::size_t shape_count);
nlohmann::json with_memory_report(nlohmann::json stats, const rt::Grid& g, std::size_t shape_count, const Options& mo);

} // namespace nesshi::machine

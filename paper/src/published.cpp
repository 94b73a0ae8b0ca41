// The paper's Tables 2, 3 and 4, copied from /work/shared/PAPER.md (millions of cycles, 512x512).
#include "paper/published.hpp"

#include <algorithm>

namespace nesshi::paper {

namespace {

constexpr Published P(double v) { return {v, false, false}; }
constexpr Published R(double v) { return {v, true, false}; }     // * reconstructed
constexpr Published Approx(double v) { return {v, true, true}; } // ≈ ... * reconstructed estimate

// scene, grid, S, M, V, S/M, M/V, S/V
constexpr PublishedTimes kTimes[] = {
    {"balls", 20, R(35173), P(33586), P(16846), P(1.04), P(1.99), P(2.08)},
    {"balls", 50, P(11525), P(8982), P(4581), P(1.28), P(1.96), P(2.51)},
    {"balls", 100, R(7308), P(4375), P(1887), P(1.67), P(2.31), P(3.87)},
    {"mount", 20, P(5771), Approx(4900), P(2329), Approx(1.17), P(2.10), P(2.46)},
    {"mount", 50, P(3109), P(1800), P(892), R(1.73), P(2.01), P(3.48)},
    {"mount", 100, P(3288), P(2453), P(1130), P(1.34), P(2.16), P(2.90)},
    {"rings", 20, P(13930), P(12484), P(6055), P(1.11), P(2.06), P(2.30)},
    {"rings", 50, P(8420), P(6214), P(3064), P(1.35), P(2.02), P(2.74)},
    {"rings", 100, P(7726), P(4471), P(2263), P(1.72), P(1.97), P(3.41)},
    {"tetra", 20, P(2096), P(1673), P(832), R(1.25), P(2.0), P(2.51)},
    {"tetra", 50, P(1951), P(1321), P(584), P(1.47), P(2.26), P(3.33)},
    {"tetra", 100, P(2976), P(2540), P(1114), P(1.17), P(2.27), P(2.67)},
    {"tree", 20, P(38552), P(36768), P(17857), P(1.04), P(2.05), P(2.15)},
    {"tree", 50, P(17839), P(14915), P(7337), P(1.19), P(2.03), P(2.43)},
    {"tree", 100, P(10651), P(5851), P(3060), R(1.82), R(1.91), R(3.48)},
};

// scene, grid, OS, IC, SC processing, OS:IC:SC load ratio (true: the printed ratio is suspect)
// clang-format off
constexpr PublishedStages kStages[] = {
    {"balls", 20, 442, 16569, 176, {2, 76, 1}},
    {"balls", 50, 868, 4209, 180, {4, 20, 1}},
    {"balls", 100, 1593, 1167, 178, {8, 6, 1}},
    {"mount", 20, 247, 2058, 60, {4, 25, 1}},
    {"mount", 50, 494, 637, 64, {6, 8, 1}},
    {"mount", 100, 914, 243, 55, {13, 4, 1}},
    {"rings", 20, 357, 5762, 120, {3, 37, 1}},
    {"rings", 50, 681, 2703, 122, {6, 18, 1}},
    {"rings", 100, 1139, 1800, 124, {9, 13, 1}},
    {"tetra", 20, 215, 622, 17, {9, 24, 1}},
    {"tetra", 50, 539, 222, 31, {14, 6, 1}},
    {"tetra", 100, 1070, 142, 23, {33, 5, 1}},
    {"tree", 20, 571, 17514, 83, {6, 15, 1}, true},
    {"tree", 50, 1146, 6895, 81, {12, 6, 1}, true},
    {"tree", 100, 2016, 2412, 80, {19, 23, 1}},
};
// clang-format on

// Speed-ups and utilisation are the same ranges for every scene; IC's ILP depends on the shapes
// (triangles parallelise better than quadrics).
constexpr PublishedVliw vliw(std::string_view scene, PublishedRange ic_ilp) {
    return {scene,        {2.21, 2.29}, {1.85, 2.00}, {2.00, 2.31}, {1.86, 2.03},
            {2.27, 2.29}, ic_ilp,       {0.56, 0.57}, {0.50, 0.57}};
}
constexpr PublishedVliw kVliw[] = {
    vliw("balls", {2.01, 2.02}), vliw("mount", {2.27, 2.31}), vliw("rings", {2.06, 2.11}),
    vliw("tetra", {2.27, 2.31}), vliw("tree", {2.06, 2.11}),
};

// Table 2 of seed-paper-ja.txt: the rows after each stage's processing time are its communication
// and its wait; processing + communication + wait = the total in every column.
constexpr PublishedComm kComm[] = {
    {"balls", 20, 203, 186, 44},  {"balls", 50, 225, 207, 45},  {"balls", 100, 275, 257, 45},
    {"mount", 20, 104, 97, 24},   {"mount", 50, 114, 106, 24},  {"mount", 100, 143, 136, 24},
    {"rings", 20, 251, 236, 36},  {"rings", 50, 278, 264, 36},  {"rings", 100, 310, 296, 36},
    {"tetra", 20, 41, 33, 10},    {"tetra", 50, 44, 37, 10},    {"tetra", 100, 43, 36, 10},
    {"tree", 20, 237, 211, 33},   {"tree", 50, 237, 211, 33},   {"tree", 100, 237, 211, 33},
};

template <class Row> const Row* find_row(std::span<const Row> rows, std::string_view scene, int grid) {
    auto it = std::find_if(rows.begin(), rows.end(), [&](const Row& r) { return r.scene == scene && r.grid == grid; });
    return it == rows.end() ? nullptr : &*it;
}

} // namespace

std::span<const PublishedTimes> published_times() { return kTimes; }
std::span<const PublishedStages> published_stages() { return kStages; }
std::span<const PublishedVliw> published_vliw() { return kVliw; }
std::span<const PublishedComm> published_comm() { return kComm; }

const PublishedTimes* find_published_times(std::string_view scene, int grid) {
    return find_row(published_times(), scene, grid);
}
const PublishedStages* find_published_stages(std::string_view scene, int grid) {
    return find_row(published_stages(), scene, grid);
}
const PublishedComm* find_published_comm(std::string_view scene, int grid) {
    return find_row(published_comm(), scene, grid);
}
const PublishedVliw* find_published_vliw(std::string_view scene) {
    auto rows = published_vliw();
    auto it = std::find_if(rows.begin(), rows.end(), [&](const PublishedVliw& r) { return r.scene == scene; });
    return it == rows.end() ? nullptr : &*it;
}

} // namespace nesshi::paper

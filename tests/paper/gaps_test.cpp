// The gap attribution without renders: pricing at the paper's step costs, the factors, the adopted
// hypotheses, the line fit and the reports, on hand-made counts whose answers are known.
#include "paper/gaps.hpp"
#include "paper/paper.hpp"
#include "paper/published.hpp"

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "rt/scene.hpp"

#include <algorithm>

using namespace nesshi::paper;

namespace {

// Counts whose paper-priced cycles are round: OS = 60 x 1e6 + 11 x 1e7 = 170 M; IC = 50 x 2e6 +
// 61 x 1e6 + 61 x 3e6 = 344 M (two-roots pricing: 50 x 2e6 + 61 x 1e6 + 11 x 3e6 = 194 M).
WorkCounts round_counts() {
    WorkCounts w;
    w.eye_rays = 1e6;
    w.rays = 2e6;
    w.steps = 1e7;
    w.visits = 4e6;
    w.triangle_tests = 2e6;
    w.quadric_tests = 4e6;
    w.quadric_two_roots = 1e6;
    return w;
}

} // namespace

TEST_CASE("The paper's step costs price a workload", "[gaps]") {
    const WorkCounts w = round_counts();
    CHECK(os_cycles(w, paper_prices()) == Approx(170e6));
    CHECK(ic_cycles(w, paper_prices()) == Approx(344e6));
    const HypothesisResult h = two_roots_hypothesis(w);
    CHECK(h.name == "two roots");
    CHECK(h.os == Approx(170e6)); // pricing a quadric miss changes nothing on OS
    CHECK(h.ic == Approx(194e6));
    const HypothesisResult every = init_every_ray_hypothesis(w);
    CHECK(every.os == Approx(60 * 2e6 + 11 * 1e7)); // 2e6 rays, not 1e6 eye rays
    CHECK(every.ic == Approx(344e6));
}

TEST_CASE("The paper's communication columns add up with processing and wait to its totals", "[gaps]") {
    CHECK(published_comm().size() == 15);
    // Spot checks against seed-paper-ja.txt's Table 2: balls 20 OS 442 + 203 + 16,200 = 16,845.
    const PublishedComm* c = find_published_comm("balls", 20);
    REQUIRE(c);
    CHECK(c->os == 203);
    CHECK(c->ic == 186);
    CHECK(c->sc == 44);
    CHECK(find_published_comm("tree", 100)->os == 237);
    CHECK_FALSE(find_published_comm("gears", 20));
    for (const PublishedComm& pc : published_comm()) CHECK(find_published_stages(pc.scene, pc.grid));
}

TEST_CASE("A row's factors multiply to the paper over ours", "[gaps]") {
    OursCell ours;
    ours.counts = round_counts();
    ours.os = 85e6;  // our kernels twice as fast as the paper's prices on OS
    ours.ic = 86e6;  // four times on IC
    const GapRow r = attribute("rings", 50, ours, {two_roots_hypothesis(ours.counts)});
    CHECK(r.paper_os == Approx(681e6));
    CHECK(r.paper_ic == Approx(2703e6));
    CHECK(r.os_kernel == Approx(2.0));
    CHECK(r.ic_kernel == Approx(4.0));
    CHECK_FALSE(r.os_adopted); // rings adopts no hypothesis
    CHECK_FALSE(r.ic_adopted);
    CHECK(r.os_explained == Approx(r.os_priced));
    CHECK(r.paper_os / r.ours.os == Approx(r.os_kernel * (r.os_explained / r.os_priced) * r.os_unexplained()));
    CHECK(r.paper_ic / r.ours.ic == Approx(r.ic_kernel * (r.ic_explained / r.ic_priced) * r.ic_unexplained()));
    CHECK(r.implied_steps == Approx((681e6 - 60.0 * 512 * 512) / 11));
    CHECK(r.implied_visits == Approx(264e6 / 25));
    CHECK(r.implied_tests == Approx(2703e6 / (344e6 / 6e6)));
}

TEST_CASE("An adopted hypothesis explains its part of the gap", "[gaps]") {
    OursCell ours;
    ours.counts = round_counts();
    ours.os = 85e6;
    ours.ic = 86e6;
    // tetra adopts the view hypothesis, which needs its render: missing, it is an error.
    CHECK_THROWS_AS(attribute("tetra", 20, ours, {two_roots_hypothesis(ours.counts)}), PaperError);
    const HypothesisResult view{"view 22.5", 200e6, 600e6, ours.counts};
    const GapRow r = attribute("tetra", 20, ours, {two_roots_hypothesis(ours.counts), view});
    REQUIRE(r.os_adopted);
    REQUIRE(r.ic_adopted);
    CHECK(*r.ic_adopted == "view 22.5");
    CHECK(r.os_explained == Approx(200e6));
    CHECK(r.ic_explained == Approx(600e6));
    CHECK(r.os_unexplained() == Approx(215e6 / 200e6));
    CHECK(r.ic_unexplained() == Approx(622e6 / 600e6));
    // Candidates that are not adopted leave the gap unexplained.
    const GapRow b = attribute("balls", 20, ours, {two_roots_hypothesis(ours.counts)});
    CHECK_FALSE(b.ic_adopted);
    CHECK(b.ic_explained == Approx(b.ic_priced));
    CHECK_THROWS_AS(attribute("gears", 20, ours, {}), PaperError);
    OursCell none;
    CHECK_THROWS_AS(attribute("rings", 20, none, {}), PaperError);
    for (const GapAdoption& a : gap_adoptions()) {
        CHECK((a.stage == "OS" || a.stage == "IC"));
        CHECK_FALSE(a.reason.empty());
    }
}

TEST_CASE("Scene variants change the view or the floor", "[gaps]") {
    nesshi::rt::Scene sc = nesshi::rt::parse_nff("v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 45\nhither 1\nresolution 8 8\n"
                                               "f 1 0 0 1 0 0 0 0\np 4\n10 10 0\n-10 10 0\n-10 -10 0\n10 -10 0\n"
                                               "p 3\n1 0 1\n0 1 1\n0 0 1\ns 0 0 1 0.5\n",
                                               "variant.nff");
    const nesshi::rt::Scene v = apply_variant(sc, {"x", SceneVariant::Kind::view_angle, 22.5});
    CHECK(v.view.angle == 22.5);
    const SceneVariant half{"x", SceneVariant::Kind::floor_scale, 0.5};
    CHECK(half.name() == "floor x0.5");
    const nesshi::rt::Scene f = apply_variant(sc, half);
    REQUIRE(f.entities.size() == 3);
    CHECK(f.entities[0].verts[0].x == 5); // the floor, the widest polygon, scaled in x and y
    CHECK(f.entities[0].verts[2].y == -5);
    CHECK(f.entities[0].verts[0].z == 0);
    CHECK(f.entities[1].verts[0].x == 1); // the small triangle left alone
    nesshi::rt::Scene no_polygon = sc;
    no_polygon.entities.erase(no_polygon.entities.begin(), no_polygon.entities.begin() + 2);
    CHECK_THROWS_AS(apply_variant(no_polygon, half), PaperError);
}

TEST_CASE("A line fit finds slope and intercept", "[gaps]") {
    const double x[] = {1, 2, 4}, y[] = {13, 23, 43};
    const LineFit f = fit_line(x, y);
    CHECK(f.slope == Approx(10));
    CHECK(f.intercept == Approx(3));
    const double one[] = {1};
    CHECK_THROWS_AS(fit_line(one, one), PaperError);
    const double same[] = {2, 2};
    CHECK_THROWS_AS(fit_line(same, same), PaperError);
}

TEST_CASE("The gap reports carry every row", "[gaps]") {
    OursCell ours;
    ours.counts = round_counts();
    ours.os = 85e6;
    ours.ic = 86e6;
    std::vector<GapRow> rows;
    for (int g : {20, 50, 100}) {
        ours.counts.steps = 1e5 * g; // the fit needs counts that differ over the grids
        rows.push_back(attribute("rings", g, ours, {two_roots_hypothesis(ours.counts)}));
    }
    const std::string md = gaps_markdown(rows);
    CHECK(md.find("| rings | 50 | OS | 681.0 | 85.00 | 8.01 | 1.35 | 5.92 | none | 1.00 | 5.92 |") != std::string::npos);
    CHECK(md.find("paper / two roots: OS | IC |") != std::string::npos);
    CHECK(md.find("### Line fits") != std::string::npos);
    CHECK(md.find("| rings | ") != std::string::npos);
    const nlohmann::json j = nlohmann::json::parse(gaps_json(rows));
    REQUIRE(j["gaps"].size() == 3);
    CHECK(j["gaps"][1]["stages"]["IC"]["kernel"].get<double>() == Approx(4.0));
    CHECK(j["gaps"][0]["hypotheses"][0]["name"] == "two roots");
    const std::string csv = gaps_csv(rows);
    CHECK(std::count(csv.begin(), csv.end(), '\n') == 7); // header + 3 rows x 2 stages
    const std::string svg = gaps_svg(rows);
    CHECK(svg.rfind("<svg", 0) == 0);
    CHECK(svg.find("rings 100 IC") != std::string::npos);
    CHECK(svg.find("</svg>") != std::string::npos);
}

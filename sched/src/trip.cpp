// `.trip MIN[, EXPECTED]` (see trip.hpp): the directive, the whole-run cycles of a counted loop's
// code, and the report of the choice made by them (sched::TripChoice).
#include "trip.hpp"

#include "text.hpp"
#include "sched/pipeline.hpp"

#include "assembler/op_text.hpp"
#include "base/error.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <limits>

namespace nesshi::sched {

namespace {

constexpr int kMaxTrip = std::numeric_limits<std::int32_t>::max(); // a trip register holds 32 bits

[[noreturn]] void fail_at(std::string_view file, int line, const std::string& text, std::size_t at, const std::string& msg) {
    const std::size_t col = at == std::string::npos ? 0 : at;
    throw base::Error(base::SourceLoc(file, line, static_cast<int>(col + 1)),
                      fmt::format("{}\n{}\n{}^", msg, text, std::string(col, ' ')));
}

// "2x", or "2x x 4" for a kernel of 2 register copies repeated 4 times (Allocation::groups).
std::string kernel_copies(const TripChoice::Option& o) {
    return o.groups == 1 ? fmt::format("{}x", o.unroll) : fmt::format("{}x x {}", o.unroll, o.groups);
}

} // namespace

TripDirective parse_trip(const std::string& text, std::string_view file, int line) {
    const std::vector<assembler::OperandText> args = assembler::split_operation(text).operands;
    const std::size_t directive = text.find(".trip");
    if (args.empty() || args.size() > 2)
        fail_at(file, line, text, directive, ".trip takes the minimum trip count and, optionally, the expected one: "
                                             ".trip MIN[, EXPECTED]");
    int value[2] = {0, 0};
    for (std::size_t k = 0; k < args.size(); ++k) {
        const std::string& a = args[k].text;
        const std::size_t at = args[k].col;
        bool digits = !a.empty() && a.size() <= 10;
        for (char c : a) digits = digits && c >= '0' && c <= '9';
        const long long v = digits ? std::stoll(a) : 0;
        if (!digits || v < 1 || v > kMaxTrip)
            fail_at(file, line, text, at, fmt::format("the {} trip count must be an integer from 1 to {} (got '{}')",
                                                      k == 0 ? "minimum" : "expected", kMaxTrip, a));
        value[k] = static_cast<int>(v);
    }
    if (args.size() == 2 && value[1] < value[0])
        fail_at(file, line, text, args[1].col,
                fmt::format("the expected trip count {} is below the minimum {}", value[1], value[0]));
    return {value[0], args.size() == 2 ? value[1] : value[0], line};
}

RunParts whole_run_parts(const CountedShape& s, std::int64_t trips) {
    const std::int64_t a = s.alu_latency, b = s.penalty, p = s.prologue_passes, u = s.unroll;
    RunParts r;
    std::int64_t& c = r.outside;
    const std::int64_t n = trips;
    c = s.lead;
    if (s.guard) {
        c += 1; // beqz TRIP, done
        if (n == 0) {
            c += b;
            return r;
        }
    }
    if (s.short_path) {
        c += a + 1; // slti, its nops, beqz pipe
        if (n < s.min_pipelined) { // the sequential copy: body, addi TRIP and its nops, bnez; jmp done
            r.sequential_iterations = n;
            c += n * (s.body + a + 1) + (n - 1) * b + 1 + b;
            return r;
        }
        c += b;
    }
    // The kernel's copies each run an iteration; a bubble for each back branch taken, and for an
    // exit taken from a copy before the last.
    const std::int64_t kernel = n - p, copies = u * s.groups;
    const std::int64_t bubbles = (kernel - 1) / copies + (kernel % copies != 0 ? 1 : 0);
    r.kernel = kernel * s.ii + bubbles * b;
    // The exit of the last copy's rotation; all but the last laid out (rotation u - 2) jump to done.
    const std::int64_t rotation = (kernel - 1) % copies % u;
    const bool jumps = u > 1 && rotation != u - 2;
    r.fill_drain = s.setup + p * s.ii + s.entry_nops + s.tail + (jumps ? 1 + b : 0);
    return r;
}

std::int64_t whole_run_cycles(const CountedShape& s, std::int64_t trips) { return whole_run_parts(s, trips).total(); }

std::string TripChoice::text() const {
    const auto per = [&](const Option& o) { return static_cast<double>(o.cycles) / expected; };
    const auto what = [&](const Option& o) {
        return fmt::format("II {}, {} stage{}, kernel {}: {:.2f} cycles per iteration", o.ii, o.stages, o.stages == 1 ? "" : "s",
                           kernel_copies(o), per(o));
    };
    // Where the cycles go: what makes one schedule beat another.
    const auto parts = [&](const Option& o) {
        std::string t = fmt::format("{} cycles: kernel {}, fill and drain {}", o.cycles, o.kernel, o.fill_drain);
        if (o.sequential_iterations > 0)
            t += fmt::format(", {} sequential iteration{} and the tests {}", o.sequential_iterations,
                             o.sequential_iterations == 1 ? "" : "s", o.outside);
        else if (o.outside > 0)
            t += fmt::format(", tests {}", o.outside);
        return t;
    };
    std::string o = fmt::format("#   trip count: at least {}{} (.trip, line {}; fewer is an error, not checked)\n", min,
                                expected != min ? fmt::format(", expected {}", expected) : "", line);
    o += fmt::format("#   whole run at {} trips: {} ({})\n", expected, what(chosen), parts(chosen));
    const bool same = chosen.ii == first.ii && chosen.stages == first.stages && chosen.unroll == first.unroll &&
                      chosen.groups == first.groups && chosen.cycles == first.cycles;
    const std::string iis = ii_first == ii_last ? fmt::format("II {}", ii_first) : fmt::format("IIs {}..{}", ii_first, ii_last);
    if (same)
        o += fmt::format("#   chosen among {} schedule{} at {}: the first found is the fastest\n", candidates,
                         candidates == 1 ? "" : "s", iis);
    else
        o += fmt::format("#   chosen among {} schedule{} at {}; the first found, {} would take {:.2f} cycles per iteration ({})\n",
                         candidates, candidates == 1 ? "" : "s", iis,
                         fmt::format("II {}, {} stage{}, kernel {},", first.ii, first.stages, first.stages == 1 ? "" : "s", kernel_copies(first)),
                         per(first), parts(first));
    return o;
}

std::string TripChoice::json() const {
    const auto option = [&](const Option& o) {
        return nlohmann::ordered_json{{"ii", o.ii},
                                      {"stages", o.stages},
                                      {"unroll", o.unroll},
                                      {"groups", o.groups},
                                      {"cycles", o.cycles},
                                      {"kernel", o.kernel},
                                      {"fill_drain", o.fill_drain},
                                      {"outside", o.outside},
                                      {"sequential_iterations", o.sequential_iterations},
                                      {"cycles_per_iteration", static_cast<double>(o.cycles) / expected}};
    };
    const nlohmann::ordered_json j = {{"min", min},
                                      {"expected", expected},
                                      {"line", line},
                                      {"short_path", short_path},
                                      {"candidates", candidates},
                                      {"ii_searched", {ii_first, ii_last}},
                                      {"chosen", option(chosen)},
                                      {"first_found", option(first)}};
    return j.dump();
}

} // namespace nesshi::sched

// Trace writers: one line per cycle (text), or Chrome/Perfetto trace-event JSON.
//
// Text, one line per cycle:
//        cycle     pc  what    label / bundle                         landed writes and ports
//            3      2  issue   loop+1 { iu0: addi r1, r1, -1 ; ... }  => r2=1 | IRF r2/5 w1/2 FPRF r0/5 w0/2
//            4      3  bubble                                         => f1=1.5 | IRF w0/2 FPRF w1/2
// "landed writes" are the registers whose values became visible at the start of the cycle;
// ports are this cycle's reads (issue) and landing writes against the file's port counts.
//
// Chrome: open the file in https://ui.perfetto.dev or chrome://tracing. One track per issue
// slot with one 1-unit event per operation (1 cycle = 1 us on the timeline), plus a "stall"
// track for wait and bubble cycles.
#pragma once

#include "iss/processor.hpp"

#include <cstdio>
#include <string>

namespace nesshi::iss {

class TextTracer : public Tracer {
  public:
    explicit TextTracer(std::FILE* out) : out_(out) {}
    void on_cycle(const Program& prog, const CycleEvent& ev) override;

  private:
    std::FILE* out_;
    bool header_ = false;
};

class ChromeTracer : public Tracer {
  public:
    explicit ChromeTracer(std::FILE* out) : out_(out) {}
    ~ChromeTracer() override { // call finish() first to see its errors: a destructor cannot throw
        try {
            finish();
        } catch (...) {
        }
    }
    void on_cycle(const Program& prog, const CycleEvent& ev) override;
    void finish(); // closes the JSON document (idempotent)

  private:
    void event(const std::string& json);
    std::FILE* out_;
    bool started_ = false, finished_ = false, first_ = true;
};

// "r1=5" / "f2=1.5" (floats as the assembler writes them).
std::string format_reg_value(uint16_t reg, uint32_t value);

} // namespace nesshi::iss

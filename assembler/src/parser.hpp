// Parses source text into records (labels, directives, bundles) that keep file:line:col.
// `.include` is expanded here; everything else is interpreted by layout.cpp.
#pragma once

#include "records.hpp"

#include "assembler/assembler.hpp"

#include <vector>

namespace nesshi::assembler {

class Parser {
  public:
    Parser(SourceSet& sources, Diagnostics& diags, const isa::Machine& m, const AsmOptions& opts)
        : sources_(sources), diags_(diags), m_(m), opts_(opts) {}
    void parse_file(int file, int depth = 0);
    std::vector<Item> items;

  private:
    void parse_line(int file, int line, int depth);
    size_t parse_op_at(const std::vector<Token>& toks, size_t i, int file, int line, bool in_bundle);
    void directive(const std::vector<Token>& toks, size_t i, int file, int line, int depth);
    void include(const Token& name, Loc loc, int file, int depth);
    void close_open_bundle();

    SourceSet& sources_;
    Diagnostics& diags_;
    const isa::Machine& m_;
    const AsmOptions& opts_;
    bool in_bundle_ = false;
    BundleRec bundle_;
};

// Every directive the assembler knows, with the leading dot.
bool known_directive(std::string_view name);

} // namespace nesshi::assembler

// First pass: sections, addresses and symbols. Code labels are bundle indices, data labels
// byte addresses, `.equ` names constant expressions evaluated on demand (forward references
// allowed, cycles reported). Directives that change the layout (.data ADDR, .space, .align)
// must be computable where they stand. A .equ is evaluated once: its value is kept with the
// latest definition it needs, which says where it is known (so `.equ aN, aN-1+aN-1` chains
// cost linear time, not exponential), and chains share one nesting limit (so they cannot
// exhaust the stack).
#pragma once

#include "expr.hpp"
#include "records.hpp"

#include "isa/machine.hpp"

#include <map>
#include <string>
#include <vector>

namespace nesshi::assembler {

struct SymbolDef {
    enum class Kind { Code, Data, Equ } kind = Kind::Code;
    int64_t value = 0;
    Loc loc;
    size_t order = 0;        // item index of the definition
    std::vector<Token> expr; // .equ
    int state = 0;           // .equ: 0 new, 1 evaluating, 2 done, 3 failed
    std::string error;       // .equ failure
    size_t deps = 0;         // .equ done: the latest definition (item index) its value needs
    bool global = false;
};

// Largest data section the assembler builds (bigger than any preset memory).
inline constexpr uint64_t kMaxSection = uint64_t{1} << 28;

struct DataSec {
    uint32_t address = 0;
    uint64_t size = 0;
    Loc loc;
    std::vector<uint8_t> bytes; // filled in the second pass
};

// A data directive to evaluate in the second pass.
struct DataFill {
    const DirectiveRec* dir;
    size_t section;
    uint64_t offset;
};

struct PlacedBundle {
    BundleRec* rec;
    std::string file; // line-table file name (.file or the real file)
    uint32_t line = 0;
};

class Layout {
  public:
    Layout(const SourceSet& sources, Diagnostics& diags, const isa::Machine& m)
        : sources_(sources), diags_(diags), m_(m) {}
    void run(std::vector<Item>& items);

    // Resolver seeing every symbol (second pass).
    Resolver resolver();
    std::map<std::string, SymbolDef> symbols;
    std::vector<PlacedBundle> bundles;
    std::vector<DataSec> data;
    std::vector<DataFill> fills;
    std::vector<const DirectiveRec*> globals;

  private:
    std::optional<int64_t> lookup(const Token& name, std::string& err, size_t limit);
    std::vector<std::string> symbol_names() const; // for "did you mean"
    std::optional<int64_t> evaluate_equ(const Token& name, SymbolDef& s, std::string& err, size_t limit);
    std::optional<int64_t> eval_now(const std::vector<Token>& toks, Loc loc, size_t limit);
    void define(const std::string& name, SymbolDef def);
    void directive(const DirectiveRec& d, size_t order);
    DataSec* current_data(Loc loc);

    const SourceSet& sources_;
    Diagnostics& diags_;
    const isa::Machine& m_;
    bool in_data_ = false;
    int data_index_ = -1;
    std::string logical_file_;
    int64_t pending_loc_ = -1;
    int nesting_ = 0;   // expression depth shared by an evaluation and the .equ it reaches
    int equ_depth_ = 0; // .equ evaluations in progress (for the message of a long chain)
    bool elided_ = false; // links of the failing chain left out of its message
    size_t deps_ = 0;   // latest definition the evaluation in progress has used
};

} // namespace nesshi::assembler

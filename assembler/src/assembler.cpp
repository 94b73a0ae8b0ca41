// The assembler driver: parse, lay out, encode and check, analyse hazards, emit.
#include "assembler/assembler.hpp"

#include "checks.hpp"
#include "emit.hpp"
#include "hazards.hpp"
#include "layout.hpp"
#include "listing.hpp"
#include "operands.hpp"
#include "parser.hpp"

#include "base/error.hpp"
#include "base/read_file.hpp"

#include <fmt/format.h>

namespace nesshi::assembler {

namespace {

AsmResult assemble_sources(SourceSet& sources, int main_file, const isa::Machine& m, const AsmOptions& opts) {
    Diagnostics diags(sources, opts.error_limit);
    Parser parser(sources, diags, m, opts);
    parser.parse_file(main_file);
    Layout layout(sources, diags, m);
    if (!diags.stopped()) layout.run(parser.items); // past the error limit: report and stop

    // Second pass: immediates (labels now known), then the per-bundle resource rules.
    Resolver resolve = layout.resolver();
    bool code_ok = true;
    for (PlacedBundle& b : layout.bundles) {
        if (diags.stopped()) break;
        bool ok = !b.rec->had_errors;
        for (OpRec& o : b.rec->ops) ok = resolve_imm(o, resolve, layout.bundles.size(), diags) && ok;
        if (ok) ok = check_bundle_rules(*b.rec, m, diags);
        code_ok = code_ok && ok;
    }
    if (!diags.stopped()) fill_data(layout, diags);
    if (!diags.stopped()) check_data_regions(layout, m, diags);
    if (!diags.stopped()) apply_globals(layout, diags);
    // An empty file (or one with only data) assembles, but nothing could ever run it.
    if (layout.bundles.empty() && !diags.stopped())
        diags.warning(Loc{main_file, 0, 0}, "no code: the object has no bundle to run (end a program with 'halt')");
    if (code_ok && !diags.stopped()) {
        std::vector<size_t> labels;
        for (const auto& [name, s] : layout.symbols)
            if (s.kind == SymbolDef::Kind::Code) labels.push_back(size_t(s.value));
        check_hazards(layout.bundles, m, diags, labels);
    }

    AsmResult r;
    r.errors = diags.errors();
    r.warnings = diags.warnings();
    r.ok = r.errors == 0;
    r.diagnostics = diags.render();
    for (const Diagnostic* d : diags.in_order()) {
        const std::string file = d->loc.file >= 0 ? diags.sources().files[size_t(d->loc.file)].name : "";
        r.messages.push_back({d->severity == Severity::Error, file, d->loc.line, d->loc.col, d->message});
    }
    std::string counts;
    if (r.warnings) counts = fmt::format("{} warning{}", r.warnings, r.warnings == 1 ? "" : "s");
    if (r.warnings && r.errors) counts += " and ";
    if (r.errors) counts += fmt::format("{} error{}", r.errors, r.errors == 1 ? "" : "s");
    if (!counts.empty()) r.diagnostics += counts + " generated.\n";
    if (r.ok) {
        r.object = build_object(layout, m);
        if (opts.listing) r.listing = make_listing(layout, r.object, m);
    }
    return r;
}

} // namespace

AsmResult assemble_string(std::string_view text, std::string_view filename, const isa::Machine& m,
                          const AsmOptions& opts) {
    SourceSet sources;
    int id = sources.add(std::string(filename), text);
    return assemble_sources(sources, id, m, opts);
}

AsmResult assemble_file(const std::string& path, const isa::Machine& m, const AsmOptions& opts) {
    std::string text;
    try {
        text = base::read_file(path);
    } catch (const base::Error& e) {
        AsmResult r;
        r.errors = 1;
        r.diagnostics = std::string(e.what()) + "\n";
        r.messages.push_back({true, path, 0, 0, e.message()});
        return r;
    }
    return assemble_string(text, path, m, opts);
}

std::string header_machine(std::string_view text) {
    constexpr std::string_view key = "# machine:";
    std::string_view first = text.substr(0, text.find('\n'));
    if (first.substr(0, key.size()) != key) return {};
    first.remove_prefix(key.size());
    const auto b = first.find_first_not_of(" \t");
    if (b == std::string_view::npos) return {};
    const auto e = first.find_last_not_of(" \t\r");
    return std::string(first.substr(b, e - b + 1));
}

} // namespace nesshi::assembler

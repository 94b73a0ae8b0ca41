// The assembly listing: per bundle its address, each op's encoding, slot and source text, and
// the bundle's register-port and unit usage; then the data sections.
#pragma once

#include "layout.hpp"

#include "isa/object.hpp"

namespace nesshi::assembler {

std::string make_listing(const Layout& layout, const isa::ObjectFile& obj, const isa::Machine& m);

} // namespace nesshi::assembler

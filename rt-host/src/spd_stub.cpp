#include "spd_gen.hpp"
#include <stdexcept>
namespace nesshi::rt {
void gen_balls(NffWriter&, int) { throw std::invalid_argument("balls: not yet"); }
void gen_mount(NffWriter&, int) { throw std::invalid_argument("mount: not yet"); }
void gen_rings(NffWriter&, int) { throw std::invalid_argument("rings: not yet"); }
void gen_tetra(NffWriter&, int) { throw std::invalid_argument("tetra: not yet"); }
void gen_tree(NffWriter&, int) { throw std::invalid_argument("tree: not yet"); }
}

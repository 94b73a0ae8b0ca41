// Reaches the ISS's private header through an include path, and a higher layer (layout.layers-refuses).
#include "private_helpers.hpp"
#include "paper/cells.hpp"

// Reaches the ISS's private header through an include path and by its src/ path, and a higher
// layer (layout.layers-refuses).
#include "private_helpers.hpp"
#include "iss/src/private_helpers.hpp"
#include "paper/cells.hpp"

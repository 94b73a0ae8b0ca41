// A private header of the ISS (the fixture of layout.layers-refuses).
#pragma once

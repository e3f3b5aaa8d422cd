// A PNG file written whole or not at all, its failure a status with the system's reason.
#pragma once

#include <cstddef>
#include <string>

#include "gearnvh/render/plots.h"

namespace gearnvh::render {

// Writes `bytes` to png_path through a temporary beside it and a rename (a reader never sees half
// an image); a failure removes the temporary and names the system's reason (error_number: errno).
RenderStatus WritePng(const std::string& png_path, const unsigned char* bytes, size_t size);

}  // namespace gearnvh::render

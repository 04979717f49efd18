#pragma once

/// Explicit instantiation for the one dimension Systole is built for. Use at
/// the end of a .cc file.
#define SYSTOLE_INSTANTIATE_3D(CLASS) template class CLASS<3>;

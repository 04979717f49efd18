#pragma once

/// @file
/// The boost text archives of the checkpoints, declared for the headers whose
/// save/load functions take one by reference (the sources that write or read
/// include boost/archive/text_{o,i}archive.hpp, which are too heavy for a
/// header).

namespace boost::archive
{
  class text_oarchive;
  class text_iarchive;
} // namespace boost::archive

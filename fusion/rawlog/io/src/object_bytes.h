#pragma once
// One MRPT object as the bytes CArchive writes for it, and back: the reader's calibration of
// the nested fixed-size objects and the sandbox's copies (child to parent) both use these.
// Private to rawlog_io.

#include <cstdint>
#include <memory>
#include <vector>

namespace mrpt::serialization {
class CSerializable;
}

namespace losmimo::rawlog_io {

std::vector<std::uint8_t> serialize(const mrpt::serialization::CSerializable& object);

// Throws std::runtime_error if MRPT reads a different length than `bytes` holds, and whatever
// MRPT throws on bad bytes.
std::shared_ptr<mrpt::serialization::CSerializable> deserialize(const std::vector<std::uint8_t>& bytes);

}  // namespace losmimo::rawlog_io

#include "object_bytes.h"

#include <stdexcept>

#include <mrpt/io/CMemoryStream.h>
#include <mrpt/serialization/CArchive.h>

namespace losmimo::rawlog_io {

std::vector<std::uint8_t> serialize(const mrpt::serialization::CSerializable& object) {
  mrpt::io::CMemoryStream mem;
  auto a = mrpt::serialization::archiveFrom(mem);
  a << object;
  const auto* p = static_cast<const std::uint8_t*>(mem.getRawBufferData());
  return {p, p + mem.getTotalBytesCount()};
}

std::shared_ptr<mrpt::serialization::CSerializable> deserialize(const std::vector<std::uint8_t>& bytes) {
  mrpt::io::CMemoryStream mem;
  mem.assignMemoryNotOwn(bytes.data(), bytes.size());
  auto a = mrpt::serialization::archiveFrom(mem);
  auto object = a.ReadObject();
  if (mem.getPosition() != bytes.size()) throw std::runtime_error("MRPT read a different length back");
  return object;
}

}  // namespace losmimo::rawlog_io

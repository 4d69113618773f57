#pragma once
// Reading OpenEXR files we did not write: OpenEXR 3.1 trusts the sizes in a file's header
// (it allocates an attribute's claimed size before reading it, and loses its place when a value's
// size disagrees with its type), so every reader of untrusted EXR bytes checks them first.
// Used by the height-map reader (src/surface/format_exr.cpp) and the parameter-texture reader
// (src/texture/param_texture_io.cpp).

#include <OpenEXR/ImfHeader.h>  // Imath::Box2i
#include <OpenEXR/ImfIO.h>

#include <cstdint>
#include <span>
#include <string>

namespace microbrdf::detail {

/// Sets OpenEXR's global limits once (largest image 2^20 a side, tile 2^14) and initialises the
/// library. Call before opening any EXR.
void init_openexr_limits();

/// Walks the header(s) of an EXR file image and checks every attribute's declared size against
/// the bytes there and against what its type implies. Throws FileError naming `name`.
void check_exr_header_bytes(std::span<const std::uint8_t> data, const std::string& name);

/// Checks a data window read from a checked header: corners within +-2^30, not empty, and at most
/// min(2^28, 256 * file_bytes + 2^16) samples, so a tiny compressed file cannot make the caller
/// allocate gigabytes. Returns the number of samples; throws FileError naming `name`.
std::uint64_t check_exr_data_window(const Imath::Box2i& dw, std::size_t file_bytes,
                                    const std::string& name);

/// An Imf::IStream over a byte span (no copy); reads past the end throw.
class ExrMemIStream : public Imf::IStream {
 public:
  ExrMemIStream(std::span<const std::uint8_t> data, const std::string& name);
  bool read(char c[], int n) override;
  uint64_t tellg() override { return pos_; }
  void seekg(uint64_t pos) override;
  void clear() override {}

 private:
  std::span<const std::uint8_t> data_;
  std::size_t pos_ = 0;
};

}  // namespace microbrdf::detail

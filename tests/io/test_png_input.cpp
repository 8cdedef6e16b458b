// Damaged PNG files must be refused with a message naming the file, never
// crash the reader; huge headers must be refused before allocating.

#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>

#include "core/error.hpp"
#include "io/png_image.hpp"

using namespace warpfem;
namespace fs = std::filesystem;

namespace {

using Bytes = std::string;

std::uint32_t crc32(const Bytes& data, std::size_t begin, std::size_t end) {
  std::uint32_t crc = 0xffffffffu;
  for (std::size_t i = begin; i < end; ++i) {
    crc ^= static_cast<std::uint8_t>(data[i]);
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xedb88320u & (0u - (crc & 1u)));
  }
  return ~crc;
}

void put_u32(Bytes& data, std::size_t at, std::uint32_t v) {
  for (int k = 0; k < 4; ++k)
    data[at + static_cast<std::size_t>(k)] = static_cast<char>((v >> (24 - 8 * k)) & 0xff);
}

/// Offset of the first chunk of `type` (its length field).
std::size_t chunk_offset(const Bytes& png, const std::string& type) {
  std::size_t at = 8;
  while (at + 8 <= png.size()) {
    const std::uint32_t length = (static_cast<std::uint32_t>(static_cast<std::uint8_t>(png[at])) << 24) |
                                 (static_cast<std::uint32_t>(static_cast<std::uint8_t>(png[at + 1])) << 16) |
                                 (static_cast<std::uint32_t>(static_cast<std::uint8_t>(png[at + 2])) << 8) |
                                 static_cast<std::uint8_t>(png[at + 3]);
    if (png.compare(at + 4, 4, type) == 0) return at;
    at += 12 + length;
  }
  ADD_FAILURE() << "no " << type << " chunk";
  return 0;
}

/// Rewrites the CRC of the chunk at `at` whose data is `length` bytes long.
void fix_crc(Bytes& png, std::size_t at, std::size_t length) {
  put_u32(png, at + 8 + length, crc32(png, at + 4, at + 8 + length));
}

struct PngFiles {
  fs::path dir;
  Bytes good;
  PngFiles() {
    dir = fs::temp_directory_path() / ("warpfem_png_" + std::to_string(::getpid()) + "_" +
                                       ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir);
    io::Image image;
    image.width = 64;
    image.height = 48;
    image.rgba.resize(64 * 48 * 4);
    std::mt19937 random(7);
    for (auto& c : image.rgba) c = static_cast<std::uint8_t>(random());  // noise: a large IDAT
    image.pixel(3, 0)[0] = 200;
    io::write_png((dir / "good.png").string(), image);
    std::ifstream in(dir / "good.png", std::ios::binary);
    good.assign(std::istreambuf_iterator<char>(in), {});
  }
  ~PngFiles() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
  std::string write(const std::string& name, const Bytes& bytes) const {
    std::ofstream(dir / name, std::ios::binary) << bytes;
    return (dir / name).string();
  }
};

std::string error_of(const std::string& path) {
  try {
    io::read_png(path);
  } catch (const Error& e) {
    return e.what();
  }
  return "(no error)";
}

void expect_refused(const std::string& path, const std::string& part) {
  const std::string m = error_of(path);
  EXPECT_EQ(m.rfind(path + ": ", 0), 0u) << m;
  EXPECT_NE(m.find(part), std::string::npos) << "message: " << m << "\nexpected to contain: " << part;
}

}  // namespace

TEST(PngInput, ValidFileReadsBackBottomRowFirst) {
  PngFiles f;
  const io::Image image = io::read_png((f.dir / "good.png").string());
  EXPECT_EQ(image.width, 64);
  EXPECT_EQ(image.height, 48);
  EXPECT_EQ(image.pixel(3, 0)[0], 200);
  ASSERT_GT(f.good.size(), 4000u);
}

TEST(PngInput, TruncatedFileIsRefused) {
  PngFiles f;
  expect_refused(f.write("cut.png", f.good.substr(0, 400)), "cannot decode the PNG");
  expect_refused(f.write("cut20.png", f.good.substr(0, 20)), "cannot read the PNG header");
}

TEST(PngInput, BadCrcIsRefused) {
  PngFiles f;
  Bytes png = f.good;
  const std::size_t idat = chunk_offset(png, "IDAT");
  png[idat + 8 + 100] = static_cast<char>(png[idat + 8 + 100] ^ 0x5a);  // data changed, CRC kept
  expect_refused(f.write("crc.png", png), "cannot decode the PNG");
}

TEST(PngInput, CorruptCompressedDataIsRefused) {
  PngFiles f;
  Bytes png = f.good;
  const std::size_t idat = chunk_offset(png, "IDAT");
  const std::size_t length = static_cast<std::size_t>(static_cast<std::uint8_t>(png[idat + 2])) << 8 |
                             static_cast<std::uint8_t>(png[idat + 3]);
  for (std::size_t i = 2; i < 40; ++i) png[idat + 8 + i] = static_cast<char>(0xff);  // CRC made valid again
  fix_crc(png, idat, length);
  expect_refused(f.write("data.png", png), "cannot decode the PNG");
}

TEST(PngInput, EmptyHeaderIsRefused) {
  PngFiles f;
  Bytes png = f.good;
  const std::size_t ihdr = chunk_offset(png, "IHDR");
  put_u32(png, ihdr + 8, 0);
  put_u32(png, ihdr + 12, 0);
  fix_crc(png, ihdr, 13);
  expect_refused(f.write("empty.png", png), "cannot read the PNG header");
}

TEST(PngInput, HugeHeaderIsRefusedBeforeAllocating) {
  PngFiles f;
  Bytes png = f.good;
  const std::size_t ihdr = chunk_offset(png, "IHDR");
  put_u32(png, ihdr + 8, 100000);
  put_u32(png, ihdr + 12, 100000);
  fix_crc(png, ihdr, 13);
  expect_refused(f.write("huge.png", png), "claims 100000 x 100000 pixels, more than the limit of 268435456");
}

TEST(PngInput, NotAPngAndDirectoryAreRefused) {
  PngFiles f;
  expect_refused(f.write("text.png", "hello, this is not a picture"), "cannot read the PNG header");
  expect_refused(f.dir.string(), "is a directory");
}

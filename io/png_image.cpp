#include "io/png_image.hpp"

#include <png.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkPointData.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <system_error>

#include "core/error.hpp"
#include "io/atomic_file.hpp"

namespace warpfem::io {

Image read_png(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec))
    throw Error("image file does not exist", {.file = path, .key_path = "", .hint = "check the path"});
  if (std::filesystem::is_directory(path, ec))
    throw Error("is a directory, not a PNG file", {.file = path, .key_path = "", .hint = "give a .png file"});
  // libpng's simplified API checks the signature, chunk lengths, CRCs and the
  // compressed data and reports failures in `message` (VTK's reader crashes
  // on truncated or corrupt files).
  png_image png{};
  png.version = PNG_IMAGE_VERSION;
  const auto fail = [&](const std::string& what) {
    const std::string detail = png.message[0] ? std::string(": ") + png.message : "";
    png_image_free(&png);
    return Error(what + detail, {.file = path,
                                 .key_path = "",
                                 .hint = "the file is damaged or not a PNG; "
                                         "re-export it as PNG"});
  };
  if (!png_image_begin_read_from_file(&png, path.c_str())) throw fail("cannot read the PNG header");
  const std::uint64_t pixels = std::uint64_t{png.width} * png.height;
  if (png.width == 0 || png.height == 0) throw fail("the PNG is empty (0 pixels)");
  if (pixels > kMaxImagePixels) {
    png_image_free(&png);
    throw Error("the PNG claims " + std::to_string(png.width) + " x " + std::to_string(png.height) +
                    " pixels, more than the limit of " + std::to_string(kMaxImagePixels),
                {.file = path, .key_path = "", .hint = "scale the image down"});
  }
  png.format = PNG_FORMAT_RGBA;
  Image img;
  img.width = static_cast<int>(png.width);
  img.height = static_cast<int>(png.height);
  img.rgba.resize(static_cast<std::size_t>(pixels) * 4);
  // A negative stride stores the bottom row first, as Image expects.
  const auto stride = -static_cast<png_int_32>(PNG_IMAGE_ROW_STRIDE(png));
  if (!png_image_finish_read(&png, nullptr, img.rgba.data(), stride, nullptr))
    throw fail("cannot decode the PNG");
  png_image_free(&png);
  return img;
}

void write_png(const std::string& path, const Image& image) {
  vtkNew<vtkImageData> data;
  data->SetDimensions(image.width, image.height, 1);
  data->AllocateScalars(VTK_UNSIGNED_CHAR, 4);
  std::copy(image.rgba.begin(), image.rgba.end(), static_cast<std::uint8_t*>(data->GetScalarPointer()));
  write_atomically(path, [&](const std::string& tmp) {
    vtkNew<vtkPNGWriter> writer;
    writer->SetInputData(data);
    writer->SetFileName(tmp.c_str());
    writer->Write();
    if (writer->GetErrorCode() != 0)
      throw Error("VTK could not write the PNG",
                  {.file = path,
                   .key_path = "",
                   .hint = "check free disk space and permissions; the previous file, if any, is unchanged"});
    check_png_complete(tmp, path);
  });
}

void check_png_complete(const std::string& path, const std::string& reported_path) {
  static const unsigned char signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  // The last chunk of every PNG: length 0, type "IEND", its fixed CRC.
  static const unsigned char iend[12] = {0, 0, 0, 0, 'I', 'E', 'N', 'D', 0xae, 0x42, 0x60, 0x82};
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  const std::streamoff size = in ? static_cast<std::streamoff>(in.tellg()) : -1;
  unsigned char head[8] = {}, tail[12] = {};
  bool complete = size >= 8 + 12;
  if (complete) {
    in.seekg(0);
    in.read(reinterpret_cast<char*>(head), sizeof head);
    in.seekg(size - 12);
    in.read(reinterpret_cast<char*>(tail), sizeof tail);
    complete = in && std::equal(head, head + 8, signature) && std::equal(tail, tail + 12, iend);
  }
  if (!complete)
    throw Error(
        "the written PNG is incomplete (" + std::to_string(std::max<std::streamoff>(size, 0)) + " bytes)",
        {.file = reported_path,
         .key_path = "",
         .hint = "check free disk space; the previous file, if any, is unchanged"});
}

}  // namespace warpfem::io

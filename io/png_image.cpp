#include "io/png_image.hpp"

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>
#include <vtkPNGWriter.h>
#include <vtkPointData.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "core/error.hpp"
#include "io/atomic_file.hpp"

namespace warpfem::io {

Image read_png(const std::string& path) {
  if (!std::filesystem::exists(path))
    throw Error("image file does not exist", {.file = path, .key_path = "", .hint = "check the path"});
  vtkNew<vtkPNGReader> reader;
  if (!reader->CanReadFile(path.c_str()))
    throw Error("not a PNG file", {.file = path, .key_path = "", .hint = "convert the image to PNG"});
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkImageData* data = reader->GetOutput();
  int dims[3];
  data->GetDimensions(dims);
  const int comps = data->GetNumberOfScalarComponents();
  if (dims[0] <= 0 || dims[1] <= 0 || comps < 1 || comps > 4 || data->GetScalarType() != VTK_UNSIGNED_CHAR)
    throw Error("unsupported PNG (need 8-bit gray, gray+alpha, RGB or RGBA)",
                {.file = path, .key_path = "", .hint = ""});
  Image img;
  img.width = dims[0];
  img.height = dims[1];
  img.rgba.resize(static_cast<std::size_t>(img.width) * img.height * 4);
  const auto* src = static_cast<const std::uint8_t*>(data->GetScalarPointer());
  for (std::size_t p = 0; p < static_cast<std::size_t>(img.width) * img.height; ++p) {
    const std::uint8_t* s = src + p * comps;
    std::uint8_t* d = &img.rgba[4 * p];
    if (comps <= 2) {
      d[0] = d[1] = d[2] = s[0];
      d[3] = comps == 2 ? s[1] : 255;
    } else {
      d[0] = s[0], d[1] = s[1], d[2] = s[2];
      d[3] = comps == 4 ? s[3] : 255;
    }
  }
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

// Image, PNG I/O and the display check.
#include <X11/Xlib.h>
#include <png.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkPointData.h>
#include <vtkUnsignedCharArray.h>

#include <cstdlib>
#include <cstring>
#include <memory>
#include <vector>

#include "canopy/common/atomic_file.h"
#include "canopy/common/error.h"
#include "figures/figures.h"
#include "figures/vtk_image.h"

namespace canopy::figures {

Image::Image(int w, int h, std::array<std::uint8_t, 3> fill) : width(w), height(h) {
  if (w <= 0 || h <= 0) throw common::Error("image size must be positive");
  rgb.resize(3 * static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
  for (std::size_t i = 0; i < rgb.size(); i += 3) {
    rgb[i] = fill[0];
    rgb[i + 1] = fill[1];
    rgb[i + 2] = fill[2];
  }
}

namespace detail {

Image from_vtk(vtkImageData* data, const std::string& name) {
  int dims[3];
  data->GetDimensions(dims);
  vtkDataArray* scalars = data->GetPointData()->GetScalars();
  if (dims[0] <= 0 || dims[1] <= 0 || scalars == nullptr) { throw common::DataError(name, "no image data"); }
  auto* array = vtkUnsignedCharArray::SafeDownCast(scalars);
  const int nc = scalars->GetNumberOfComponents();
  if (array == nullptr || nc < 1 || nc > 4) {
    throw common::DataError(name, "not an 8-bit grey/RGB(A) image (16-bit PNGs are not supported)");
  }
  Image out(dims[0], dims[1]);
  const unsigned char* src = array->GetPointer(0);
  for (int y = 0; y < dims[1]; ++y) {
    const unsigned char* row = src + static_cast<std::size_t>(y) * dims[0] * nc;
    for (int x = 0; x < dims[0]; ++x) {
      const unsigned char* p = row + static_cast<std::size_t>(x) * nc;
      int c[3];
      int alpha = 255;
      if (nc <= 2) {
        c[0] = c[1] = c[2] = p[0];
        if (nc == 2) alpha = p[1];
      } else {
        c[0] = p[0], c[1] = p[1], c[2] = p[2];
        if (nc == 4) alpha = p[3];
      }
      std::uint8_t* q = out.at(x, dims[1] - 1 - y);
      for (int k = 0; k < 3; ++k) {
        q[k] = static_cast<std::uint8_t>((c[k] * alpha + 255 * (255 - alpha) + 127) / 255);
      }
    }
  }
  return out;
}

vtkSmartPointer<vtkImageData> to_vtk(const Image& image) {
  auto data = vtkSmartPointer<vtkImageData>::New();
  data->SetDimensions(image.width, image.height, 1);
  data->AllocateScalars(VTK_UNSIGNED_CHAR, 3);
  auto* dst = static_cast<unsigned char*>(data->GetScalarPointer());
  const std::size_t row = 3 * static_cast<std::size_t>(image.width);
  for (int y = 0; y < image.height; ++y) {
    std::memcpy(dst + row * y, image.rgb.data() + row * (image.height - 1 - y), row);
  }
  return data;
}

}  // namespace detail

// Read with libpng's simplified API, not VTK's reader: VTK hands a truncated or corrupt PNG
// to libpng without an error handler that returns, and crashes (SIGSEGV) on it. libpng's
// simplified API reports every decoding error as a return value with a message.
Image read_png(const std::string& path) {
  const std::string name = common::display_name(path);
  const std::string bytes = common::read_file(path);
  static const unsigned char kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (bytes.size() < 8 || std::memcmp(bytes.data(), kSignature, 8) != 0) {
    throw common::DataError(name, "not a PNG file");
  }
  png_image png;
  std::memset(&png, 0, sizeof png);
  png.version = PNG_IMAGE_VERSION;
  // Frees libpng's state on every exit path.
  const std::unique_ptr<png_image, void (*)(png_imagep)> guard(&png, png_image_free);
  if (png_image_begin_read_from_memory(&png, bytes.data(), bytes.size()) == 0) {
    throw common::DataError(name, std::string("unreadable PNG: ") + png.message);
  }
  // Bounded memory: the header alone must not make us allocate gigabytes.
  constexpr png_uint_32 kMaxSide = 8192;
  if (png.width == 0 || png.height == 0 || png.width > kMaxSide || png.height > kMaxSide) {
    throw common::DataError(name, "PNG of " + std::to_string(png.width) + " x " + std::to_string(png.height) +
                                      " pixels (at most 8192 x 8192)");
  }
  png.format = PNG_FORMAT_RGBA;
  std::vector<std::uint8_t> rgba(PNG_IMAGE_SIZE(png));
  if (png_image_finish_read(&png, nullptr, rgba.data(), 0, nullptr) == 0) {
    throw common::DataError(name, std::string("unreadable PNG: ") + png.message);
  }
  const int w = static_cast<int>(png.width), h = static_cast<int>(png.height);
  Image out(w, h);
  for (std::size_t i = 0, n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h); i < n; ++i) {
    const std::uint8_t* p = &rgba[4 * i];
    const int alpha = p[3];
    for (int k = 0; k < 3; ++k) {  // composited over white, as before
      out.rgb[3 * i + static_cast<std::size_t>(k)] =
          static_cast<std::uint8_t>((p[k] * alpha + 255 * (255 - alpha) + 127) / 255);
    }
  }
  return out;
}

std::string encode_png(const Image& image) {
  if (image.width <= 0 || image.height <= 0) throw common::Error("cannot encode an empty image");
  vtkNew<vtkPNGWriter> writer;
  writer->SetInputData(detail::to_vtk(image));
  writer->WriteToMemoryOn();
  writer->SetCompressionLevel(6);
  writer->Write();
  vtkUnsignedCharArray* result = writer->GetResult();
  if (writer->GetErrorCode() != 0 || result == nullptr || result->GetNumberOfTuples() == 0) {
    throw common::Error("PNG encoding failed");
  }
  return std::string(reinterpret_cast<const char*>(result->GetPointer(0)),
                     static_cast<std::size_t>(result->GetNumberOfTuples() * result->GetNumberOfComponents()));
}

void write_png(const Image& image, const std::string& path) {
  common::write_file_atomic(path, encode_png(image));
}

void require_display() {
  // The probe connection stays open for the life of the process: an X server without
  // -noreset (xvfb-run's default) resets when its last client disconnects, and VTK's own
  // connection, opened right after a closed probe, then failed ("bad X server connection",
  // abort) in about 1 of 30 runs.
  static Display* probe = nullptr;
  if (probe != nullptr) return;
  const char* name = std::getenv("DISPLAY");
  if (name == nullptr || *name == '\0') {
    throw common::Error(
        "no X display (DISPLAY is unset): VTK renders through X11 here; "
        "run under 'xvfb-run -a' (Debian packages xvfb, xauth)");
  }
  probe = XOpenDisplay(nullptr);
  if (probe == nullptr) {
    throw common::Error(std::string("cannot open X display '") + name +
                        "'; run under 'xvfb-run -a' (Debian packages xvfb, xauth)");
  }
}

}  // namespace canopy::figures

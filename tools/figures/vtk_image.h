// Private to the figures tool (includes VTK): conversions between Image and vtkImageData.
#pragma once

#include <vtkImageData.h>
#include <vtkSmartPointer.h>

#include "figures/figures.h"

namespace canopy::figures::detail {

// vtkImageData of unsigned char with 1-4 components (VTK rows bottom to top) -> Image.
// Alpha (2 or 4 components) is composited over white. Throws Error for other layouts.
Image from_vtk(vtkImageData* data, const std::string& name);
// Image -> 3-component unsigned char vtkImageData (rows bottom to top).
vtkSmartPointer<vtkImageData> to_vtk(const Image& image);

}  // namespace canopy::figures::detail

class vtkRenderWindow;

namespace canopy::figures::detail {

// Renders the window once and reads its back buffer (RGB) into an Image.
Image capture(vtkRenderWindow* window, const std::string& name);

}  // namespace canopy::figures::detail

// Point clouds in any format canopy reads: the format of an input is chosen by the file's
// first bytes (its magic), never by its name; the format of an output by the name's
// extension. See formats/README.md ("Choosing the format" and "Coordinates").
//   input : PCD (any header line or '#' first), PLY point set ("ply" and no faces),
//           LAS and LAZ ("LASF"; LAZ decompressed by formats/laz.h). "-" = stdin.
//   output: .pcd, .ply (point set, no faces), .las (LAS 1.4); "-" = PCD on stdout.
#pragma once

#include <optional>
#include <string>

#include "canopy/formats/las.h"
#include "canopy/formats/pcd.h"
#include "canopy/formats/point_cloud.h"

namespace canopy::formats {

enum class PointFormat { kPcd, kPly, kLas };

const char* format_name(PointFormat f);

// Reads a point cloud, format by magic. `tool` (e.g. "fitvox") only words the error for a
// PLY mesh ("mesh.ply: this is a PLY mesh with 812 faces; fitvox reads points ..."). Errors
// name the file and what it is (LAS, LAZ, PLY mesh, JSON, PNG, gzip, ...); file bytes quoted
// in messages are escaped, so a NUL cannot cut a message short.
PointCloud read_points(const std::string& path, const std::string& tool = "");
// The same, keeping only the fields in `fields` that the file has (the caller's require() says
// which are missing). LAS, LAZ and a DATA binary PCD file make only those columns (memory and
// time of the others saved); other PCD and PLY are read whole and the other columns dropped.
PointCloud read_points(const std::string& path, const std::string& tool, const FieldSelection& fields);
// The same; `las_header` (not null) gets the header block of a LAS or LAZ file as the reader
// read it (read_las's `header`: standard input and FIFOs too, their CRS EVLRs too), and none
// for PCD and PLY. A caller that wants the file's CRS records (las_crs.h) need not read the
// file again.
PointCloud read_points(const std::string& path, const std::string& tool, const FieldSelection& fields,
                       std::optional<LasHeaderBlock>* las_header);
PointCloud parse_points(const std::string& bytes, const std::string& name, const std::string& tool = "");

// What a file's bytes are, for messages of readers that expect something else (e.g. ncut
// given a LAS): "a LAS file", "a LAZ file (compressed LAS)", "a PLY mesh (812 faces)",
// "a PLY point set", "a PCD point cloud", "a JSON document (canopy.segment_graph)",
// "a PNG image", "empty file", ... Looks only at the first bytes and the PLY header.
std::string describe_content(const std::string& bytes);

// Output format from the path's extension (case-insensitive); "-" = PCD. Any other name
// (unknown or no extension, .laz) throws common::UsageError saying which extensions exist:
// tools call it before their work so a mistyped output costs nothing.
PointFormat output_format(const std::string& path);

// Writes atomically in the format output_format(path) gives. Coordinates are never silently
// quantised: see promote_coordinates().
void write_points(const PointCloud& cloud, const std::string& path);
// The same; a PCD output uses `pcd`'s DATA encoding (binary_compressed is PCL tools' default).
void write_points(const PointCloud& cloud, const std::string& path, const PcdWriteOptions& pcd);
// The bytes write_points writes for `path` (format by its extension, coordinates promoted), for
// a tool that commits them together with other outputs (common::OutputSet).
std::string serialize_points(const PointCloud& cloud, const std::string& path,
                             const PcdWriteOptions& pcd = PcdWriteOptions{});
// "binary" | "binary_compressed" | "ascii" (a tool's --pcd-encoding) -> options; else UsageError.
PcdWriteOptions parse_pcd_encoding(const std::string& name);

// Float32 x y z columns are turned into float64 when float32 would move any coordinate by
// more than kFloat32CoordinateTolerance (that happens beyond ~2 km from the origin, e.g. in
// UTM or State Plane coordinates). Returns whether any column changed. write_points calls it.
inline constexpr double kFloat32CoordinateTolerance = 1e-4;  // m
bool promote_coordinates(PointCloud* cloud);

}  // namespace canopy::formats

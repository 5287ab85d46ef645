// Every format the tool reads, on files written here: the same square (two triangles, or one quad)
// and the same tetrahedron in each, with the extras real files carry.
#include "ricci/io/mesh_io.h"

#include <zlib.h>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "ricci/mesh/errors.h"
#include "test_meshes.h"

namespace ricci {
namespace {

std::string write_file(const std::string& name, const std::string& bytes) {
  const std::string path = ::testing::TempDir() + "/" + name;
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

template <class T>
void put(std::string& out, T x, bool big_endian = false) {
  char b[sizeof(T)];
  std::memcpy(b, &x, sizeof(T));
  if (big_endian) std::reverse(b, b + sizeof(T));
  out.append(b, sizeof(T));
}

const char* kTetrahedronObj =
    "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n";

void expect_tetrahedron(const CompactMesh& mesh) {
  EXPECT_EQ(mesh.num_vertices(), 4);
  EXPECT_EQ(mesh.num_faces(), 4);
  EXPECT_TRUE(mesh.is_closed());
  EXPECT_EQ(mesh.genus(), 0);
  EXPECT_EQ(mesh.positions()[3], Eigen::Vector3d(0, 0, 1));
}

TEST(MeshIo, ReadsTheTetrahedronAsObjAndOff) {
  // Every OBJ file used to be refused ("1 unreferenced vertices"): the tetrahedron reproduced it.
  expect_tetrahedron(read_mesh(write_file("tet.obj", kTetrahedronObj)));
  expect_tetrahedron(read_mesh(write_file(
      "tet.off", "OFF\n4 4 6\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n")));
}

TEST(MeshIo, ReadsTextWithAByteOrderMark) {
  // UTF-8's mark made the first vertex's keyword unknown: its faces referred past the vertices.
  expect_tetrahedron(
      read_mesh(write_file("tet-utf8.obj", "\xEF\xBB\xBF" + std::string(kTetrahedronObj))));
  // UTF-16, as Windows tools write it, in both byte orders.
  for (const bool big : {true, false}) {
    std::string utf16 = big ? "\xFE\xFF" : "\xFF\xFE";
    for (const char c : std::string(kTetrahedronObj)) {
      utf16 += big ? std::string{'\0', c} : std::string{c, '\0'};
    }
    expect_tetrahedron(read_mesh(write_file(big ? "tet-utf16be.obj" : "tet-utf16le.obj", utf16)));
  }
  // A character outside ASCII says so (an e with an acute accent in a comment).
  const std::string accented = std::string("\xFF\xFE#\0\xE9\0\n\0", 8);
  try {
    read_mesh(write_file("accented.obj", accented + std::string(kTetrahedronObj)));
    FAIL() << "expected IoError";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("UTF-16"), std::string::npos) << e.what();
  }
}

TEST(MeshIo, ObjWithTextureNormalsGroupsMaterialsAndPolygons) {
  const std::string obj =
      "# exported\nmtllib square.mtl\no square\nv 0 0 0\nv 1 0 0\nv 1 1 0 1.0\nv 0 1 0\n"
      "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\ng top\nusemtl paper\ns off\n"
      "f 1/1/1 2/2/1 3/3/1 4/4/1\n"
      "v 0.5 0.5 1\nf -1//1 -4//1 -5//1\n";  // negative: relative to the last vertex
  const MeshFile file = read_mesh_file(write_file("square.obj", obj));
  EXPECT_EQ(file.format, "obj");
  ASSERT_EQ(file.positions.size(), 5u);
  ASSERT_EQ(file.triangles.size(), 3u);
  EXPECT_EQ(file.polygons, 1);
  // The quad as a fan from its first corner.
  EXPECT_EQ(file.triangles[0], (std::array<int, 3>{0, 1, 2}));
  EXPECT_EQ(file.triangles[1], (std::array<int, 3>{0, 2, 3}));
  EXPECT_EQ(file.triangles[2], (std::array<int, 3>{4, 1, 0}));
}

TEST(MeshIo, OffWithCommentsColorsAndPolygons) {
  const std::string off =
      "COFF\n# a square as one quad\n\n4 1 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n"
      "1 1 0 0 0 255 255  # corner\n0 1 0 9 9 9 255\n4 0 1 2 3 128 128 128\n";
  const MeshFile file = read_mesh_file(write_file("square.off", off));
  EXPECT_EQ(file.positions.size(), 4u);
  EXPECT_EQ(file.triangles.size(), 2u);
  EXPECT_EQ(file.polygons, 1);
  EXPECT_EQ(read_mesh(write_file("square2.off", off)).num_boundary_loops(), 1);
}

TEST(MeshIo, NumbersInEveryWrittenForm) {
  // Exponents, signs and C's hexadecimal floats (strtod's syntax, which from_chars alone lacks).
  const std::string off = "OFF\n3 1 0\n+0.5 -0 1E2\n1e-3 0x1p-1 +7\n.25 2. -1.5e+1\n3 0 1 2\n";
  const MeshFile file = read_mesh_file(write_file("numbers.off", off));
  ASSERT_EQ(file.positions.size(), 3u);
  EXPECT_EQ(file.positions[0], Eigen::Vector3d(0.5, 0, 100));
  EXPECT_EQ(file.positions[1], Eigen::Vector3d(0.001, 0.5, 7));
  EXPECT_EQ(file.positions[2], Eigen::Vector3d(0.25, 2, -15));
  EXPECT_THROW(read_mesh_file(write_file("bad-number.off", "OFF\n3 1 0\n1 2 3x\n0 0 0\n1 1 1\n")),
               IoError);
}

TEST(MeshIo, PlyAsciiWithExtraPropertiesAndElements) {
  const std::string ply =
      "ply\nformat ascii 1.0\ncomment made by hand\nmade by hand, no comment keyword\n"
      "element vertex 4\nproperty float x\n"
      "property float y\nproperty float z\nproperty uchar red\nproperty float confidence\n"
      "element face 1\nproperty list uchar int vertex_indices\nproperty uchar flags\n"
      "element material 1\nproperty float shine\nend_header\n"
      "0 0 0 1 0.5\n1 0 0 2 0.5\n1 1 0 3 0.5\n0 1 0 4 0.5\n4 0 1 2 3 7\n0.25\n";
  const MeshFile file = read_mesh_file(write_file("square.ply", ply));
  EXPECT_EQ(file.format, "ply");
  ASSERT_EQ(file.positions.size(), 4u);
  EXPECT_EQ(file.positions[2], Eigen::Vector3d(1, 1, 0));
  EXPECT_EQ(file.triangles.size(), 2u);
}

TEST(MeshIo, PlyWhoseFirstWordIsInCapitals) {
  // COMPAS writes "PLY" where the format says "ply" (its tubemesh.ply was refused: "no PLY
  // header"); read as PLY by its name and by its first bytes.
  const std::string ply =
      "PLY\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
      "property float z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n";
  expect_tetrahedron(read_mesh(write_file("tet-capitals.ply", ply)));
  const MeshFile sniffed = read_mesh_file(write_file("tet-capitals.mesh", ply));
  EXPECT_EQ(sniffed.format, "ply");
  EXPECT_EQ(sniffed.triangles.size(), 4u);
  EXPECT_THROW(read_mesh(write_file("not.ply", "PLX\nend_header\n")), IoError);
}

std::string binary_ply(bool big_endian) {
  std::string out = std::string("ply\nformat ") +
                    (big_endian ? "binary_big_endian" : "binary_little_endian") +
                    " 1.0\nelement vertex 4\nproperty double x\nproperty double y\n"
                    "property double z\nproperty ushort id\nelement face 4\n"
                    "property uchar extra\nproperty list uchar uint vertex_indices\nend_header\n";
  const double p[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (int v = 0; v < 4; ++v) {
    for (double x : p[v]) put(out, x, big_endian);
    put(out, static_cast<std::uint16_t>(v), big_endian);
  }
  const std::uint32_t f[4][3] = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  for (const auto& t : f) {
    put(out, static_cast<std::uint8_t>(9));
    put(out, static_cast<std::uint8_t>(3));
    for (std::uint32_t v : t) put(out, v, big_endian);
  }
  return out;
}

TEST(MeshIo, PlyBinaryBothByteOrders) {
  expect_tetrahedron(read_mesh(write_file("tet_le.ply", binary_ply(false))));
  expect_tetrahedron(read_mesh(write_file("tet_be.ply", binary_ply(true))));
}

TEST(MeshIo, StlAsciiAndBinaryMergeCorners) {
  const float tri[4][3][3] = {{{0, 0, 0}, {0, 1, 0}, {1, 0, 0}},
                              {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}},
                              {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}},
                              {{0, 0, 0}, {0, 0, 1}, {0, 1, 0}}};
  std::string ascii = "solid tet\n";
  std::string binary(80, ' ');
  put(binary, static_cast<std::uint32_t>(4));
  for (const auto& t : tri) {
    ascii += "  facet normal 0 0 0\n    outer loop\n";
    for (int k = 0; k < 3; ++k) put(binary, 0.0f);  // the facet normal
    for (const auto& v : t) {
      ascii += "      vertex " + std::to_string(v[0]) + " " + std::to_string(v[1]) + " " +
               std::to_string(v[2]) + "\n";
      for (float x : v) put(binary, x);
    }
    put(binary, static_cast<std::uint16_t>(0));
    ascii += "    endloop\n  endfacet\n";
  }
  ascii += "endsolid tet\n";
  std::string upper = ascii;  // some exporters write the keywords in capitals
  for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  for (const auto& [name, bytes] :
       {std::pair{"tet_ascii.stl", ascii}, {"tet_upper.stl", upper}, {"tet_binary.stl", binary}}) {
    const MeshFile file = read_mesh_file(write_file(name, bytes));
    EXPECT_EQ(file.merged_corners, 8) << name;
    expect_tetrahedron(read_mesh(write_file(name, bytes)));
  }
}

std::string base64(const std::string& bytes) {
  static const char* digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  unsigned buffer = 0;
  int bits = 0;
  for (unsigned char c : bytes) {
    buffer = (buffer << 8) | c;
    bits += 8;
    while (bits >= 6) out.push_back(digits[(buffer >> (bits -= 6)) & 63]);
  }
  if (bits > 0) out.push_back(digits[(buffer << (6 - bits)) & 63]);
  while (out.size() % 4) out.push_back('=');
  return out;
}

// Deflated with a zlib header (as GIFTI writers do), or a gzip one (as gzip and nilearn's .gii.gz).
std::string deflated(const std::string& bytes, bool gzip = false) {
  z_stream z{};
  EXPECT_EQ(
      deflateInit2(&z, Z_DEFAULT_COMPRESSION, Z_DEFLATED, gzip ? 31 : 15, 8, Z_DEFAULT_STRATEGY),
      Z_OK);
  std::string out(deflateBound(&z, static_cast<uLong>(bytes.size())) + 32, '\0');
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(bytes.data()));
  z.avail_in = static_cast<uInt>(bytes.size());
  z.next_out = reinterpret_cast<Bytef*>(&out[0]);
  z.avail_out = static_cast<uInt>(out.size());
  EXPECT_EQ(deflate(&z, Z_FINISH), Z_STREAM_END);
  out.resize(z.total_out);
  deflateEnd(&z);
  return out;
}

struct GiftiWriting {
  std::string encoding = "GZipBase64Binary";
  bool big_endian = false, column_major = false;
  bool doubles = false;  // FLOAT64 vertices and INT64 triangles (nibabel before 5.1 wrote int64)
  bool gzip_header = false;
};

const double kTetrahedronPoints[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
const int kTetrahedronTriangles[4][3] = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};

// The tetrahedron as GIFTI: a per-vertex array (curvature, say) and an empty one first, which are
// no part of the surface, then its vertices and triangles, as `w` says.
std::string tetrahedron_gifti(const GiftiWriting& w) {
  std::string points, triangles;
  for (int k = 0; k < 12; ++k) {  // the k-th value in the file's order: row r, column c
    const auto [r, c] =
        w.column_major ? std::make_pair(k % 4, k / 4) : std::make_pair(k / 3, k % 3);
    const double p = kTetrahedronPoints[r][c];
    const int t = kTetrahedronTriangles[r][c];
    if (w.encoding == "ASCII") {
      points += std::to_string(p) + "\n";
      triangles += std::to_string(t) + " ";
    } else if (w.doubles) {
      put(points, p, w.big_endian);
      put(triangles, static_cast<std::int64_t>(t), w.big_endian);
    } else {
      put(points, static_cast<float>(p), w.big_endian);
      put(triangles, static_cast<std::int32_t>(t), w.big_endian);
    }
  }
  if (w.encoding == "GZipBase64Binary") {
    points = deflated(points, w.gzip_header), triangles = deflated(triangles, w.gzip_header);
  }
  if (w.encoding != "ASCII") {
    points = base64(points), triangles = base64(triangles);
    points.insert(points.size() / 2, "\n  ");  // writers wrap their base64 lines
  }
  const std::string common = std::string(" ArrayIndexingOrder='") +
                             (w.column_major ? "ColumnMajorOrder" : "RowMajorOrder") +
                             "'\n  Dimensionality = \"2\" Dim0=\"4\" Dim1=\"3\" Encoding=\"" +
                             w.encoding + "\" Endian=\"" +
                             (w.big_endian ? "BigEndian" : "LittleEndian") + "\"";
  return std::string(
             "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<GIFTI Version=\"1.0\" "
             "NumberOfDataArrays=\"4\"><MetaData/>\n"
             "<DataArray Intent=\"NIFTI_INTENT_SHAPE\" DataType=\"NIFTI_TYPE_FLOAT32\" "
             "ArrayIndexingOrder=\"RowMajorOrder\" Dimensionality=\"1\" Dim0=\"4\" "
             "Encoding=\"ASCII\" "
             "Endian=\"LittleEndian\"><Data>0.1 0.2 0.3 0.4</Data></DataArray>\n"
             "<DataArray Intent=\"NIFTI_INTENT_NONE\" DataType=\"NIFTI_TYPE_FLOAT32\" "
             "Dimensionality=\"1\" Dim0=\"0\" Encoding=\"ASCII\"><Data /></DataArray>\n"
             "<DataArray Intent=\"NIFTI_INTENT_POINTSET\" DataType=\"NIFTI_TYPE_") +
         (w.doubles ? "FLOAT64" : "FLOAT32") + "\"" + common +
         "><MetaData/><CoordinateSystemTransformMatrix/><Data>" + points +
         "</Data></DataArray>\n<DataArray Intent=\"NIFTI_INTENT_TRIANGLE\" "
         "DataType=\"NIFTI_TYPE_" +
         (w.doubles ? "INT64" : "INT32") + "\"" + common + "><Data>" + triangles +
         "</Data></DataArray>\n</GIFTI>\n";
}

void expect_tetrahedron_file(const MeshFile& file) {
  EXPECT_EQ(file.format, "gii");
  ASSERT_EQ(file.positions.size(), 4u);
  ASSERT_EQ(file.triangles.size(), 4u);
  for (int r = 0; r < 4; ++r) {
    EXPECT_EQ(file.positions[r], Eigen::Vector3d(kTetrahedronPoints[r][0], kTetrahedronPoints[r][1],
                                                 kTetrahedronPoints[r][2]));
    EXPECT_EQ(file.triangles[r],
              (std::array<int, 3>{kTetrahedronTriangles[r][0], kTetrahedronTriangles[r][1],
                                  kTetrahedronTriangles[r][2]}));
  }
}

// GIFTI surfaces, every encoding, byte order and index order the standard allows in a file of
// its own, 32- and 64-bit types, a zlib or gzip header, the file itself gzipped, and read without
// their extension too; files that are no surface are refused by name.
TEST(MeshIo, GiftiInEveryEncoding) {
  std::vector<GiftiWriting> writings;
  for (const char* encoding : {"ASCII", "Base64Binary", "GZipBase64Binary"}) {
    for (const bool big_endian : {false, true}) {
      for (const bool column_major : {false, true}) {
        writings.push_back({encoding, big_endian, column_major, false, false});
      }
    }
  }
  writings.push_back({"Base64Binary", true, true, true, false});
  writings.push_back({"GZipBase64Binary", false, false, true, true});
  for (const GiftiWriting& w : writings) {
    const std::string bytes = tetrahedron_gifti(w);
    const std::string name = "tet-" + w.encoding + (w.big_endian ? "-big" : "") +
                             (w.column_major ? "-columns" : "") + (w.doubles ? "-64" : "") +
                             (w.gzip_header ? "-gzip" : "") + ".surf.gii";
    SCOPED_TRACE(name);
    expect_tetrahedron_file(read_mesh_file(write_file(name, bytes)));
    expect_tetrahedron(read_mesh(write_file(name, bytes)));
    expect_tetrahedron_file(read_mesh_file(write_file("tet-no-extension", bytes)));
    expect_tetrahedron_file(read_mesh_file(write_file(name + ".gz", deflated(bytes, true))));
  }
  const auto message = [](const std::string& bytes) {
    try {
      read_mesh(write_file("bad.gii", bytes));
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  GiftiWriting ascii;
  ascii.encoding = "ASCII";
  std::string shape_only = tetrahedron_gifti(ascii);
  shape_only = shape_only.substr(0, shape_only.find("<DataArray Intent=\"NIFTI_INTENT_POINTSET"));
  EXPECT_NE(message(shape_only + "</GIFTI>").find("no vertices"), std::string::npos);
  std::string cut = tetrahedron_gifti({});
  const size_t data = cut.find("<Data>", cut.find("NIFTI_INTENT_TRIANGLE"));
  cut.erase(data + 6, 8);  // 6 bytes of the compressed stream
  EXPECT_NE(message(cut).find("does not inflate"), std::string::npos) << message(cut);
  // Data in an external file, as Connectome Workbench writes it: said so, not "no data".
  std::string external = tetrahedron_gifti(ascii);
  const size_t points = external.find("NIFTI_INTENT_POINTSET");
  const size_t points_data = external.find("<Data>", points);
  external.erase(points_data + 6, external.find("</Data>", points) - points_data - 6);
  external.replace(external.find("\"ASCII\"", points), 7,
                   "\"ExternalFileBinary\" ExternalFileName=\"lh.coord.dat\"");
  EXPECT_NE(message(external).find("external file ('lh.coord.dat')"), std::string::npos)
      << message(external);
  // Hostile counts and indices, refused before anything is allocated or cast.
  std::string huge = tetrahedron_gifti({});
  huge.replace(huge.find("Dim0=\"4\"", huge.find("NIFTI_INTENT_POINTSET")), 8,
               "Dim0=\"2000000000\"");
  EXPECT_NE(message(huge).find("has 48 bytes for its 6000000000 values"), std::string::npos)
      << message(huge);
  std::string negative = tetrahedron_gifti(ascii);
  const size_t triangles = negative.find("<Data>", negative.find("NIFTI_INTENT_TRIANGLE")) + 6;
  negative.replace(triangles, 1, "-1");
  EXPECT_NE(message(negative).find("has the index -1"), std::string::npos) << message(negative);
  // Arrays without an end: refused once, not searched for again at every DataArray.
  std::string unended = "<GIFTI>";
  for (int i = 0; i < 1000; ++i) unended += "<DataArray Intent=\"NIFTI_INTENT_POINTSET\"><Data>";
  EXPECT_NE(message(unended).find("does not end"), std::string::npos) << message(unended);
}

// FreeSurfer's fsaverage5 left pial surface as nilearn ships it (meshes/real-meshes.tsv):
// GZipBase64Binary arrays, float32 vertices and int32 triangles. The figures are nibabel 5.3's
// reading of the same file.
TEST(MeshIo, GiftiOfFreeSurfer) {
  const MeshFile file =
      read_mesh_file(std::string(RICCI_REAL_MESH_DIR) + "/nilearn-fsaverage5-pial-left.gii");
  ASSERT_EQ(file.positions.size(), 10242u);
  ASSERT_EQ(file.triangles.size(), 20480u);
  EXPECT_EQ(file.positions[0],
            Eigen::Vector3d(-38.735958099365234, -19.343364715576172, 67.22013854980469));
  EXPECT_EQ(file.positions.back(),
            Eigen::Vector3d(-34.49119186401367, -25.403905868530273, -24.645116806030273));
  EXPECT_EQ(file.triangles[0], (std::array<int, 3>{0, 2564, 2562}));
  EXPECT_EQ(file.triangles.back(), (std::array<int, 3>{10161, 11, 9918}));
  double sum = 0;
  for (const Eigen::Vector3d& p : file.positions) sum += p.sum();
  EXPECT_NEAR(sum, -349541.7265559135, 1e-6);
  const CompactMesh mesh =
      read_mesh(std::string(RICCI_REAL_MESH_DIR) + "/nilearn-fsaverage5-pial-left.gii");
  EXPECT_TRUE(mesh.is_closed());
  EXPECT_EQ(mesh.genus(), 0);
}

TEST(MeshIo, ReadsARealFileAndNamesWhatIsWrong) {
  EXPECT_EQ(read_mesh(test::cgal_mesh_path("eight.off")).num_vertices(), 315);
  EXPECT_THROW(read_mesh("/nonexistent/mesh.off"), IoError);
  const auto message = [](const std::string& name, const std::string& bytes) {
    try {
      read_mesh(write_file(name, bytes));
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("bad.obj", "v 0 0 0\nv 1 0 x\n").find("line 2: 'x' is not a number"),
            std::string::npos);
  EXPECT_NE(message("short.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n").find("the file ends before"),
            std::string::npos);
  EXPECT_NE(message("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n").find("refers to vertex 8"),
            std::string::npos);
  EXPECT_NE(message("bad.ply",
                    "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"
                    "end_header\n0\n")
                .find("no x, y and z"),
            std::string::npos);
  // A directory and a device are refused by what they are (they read as empty, or never end).
  for (const auto& [path, what] :
       {std::pair<std::string, std::string>{::testing::TempDir(), "is a directory"},
        {"/dev/zero", "not a regular file"}}) {
    try {
      read_mesh(path);
      ADD_FAILURE() << path << " was read";
    } catch (const IoError& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  }
  // Mesh defects are named with the file.
  EXPECT_NE(message("lonely.obj", std::string(kTetrahedronObj) + "v 5 5 5\n").find("lonely.obj"),
            std::string::npos);
}

// Hostile files (found by fuzzing the readers): indices past int's range, header counts that the
// file cannot hold, an element of no properties and 2^63 - 1 items, float indices that are no
// integer. Each is refused by one message naming what is wrong, at once.
TEST(MeshIo, HostileCountsAndIndicesAreRefusedByName) {
  const auto message = [](const std::string& name, const std::string& bytes) {
    try {
      read_mesh_file(write_file(name, bytes));
    } catch (const IoError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string square = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  EXPECT_NE(message("wrap.obj", square + "f 4294967297 2 3\n").find("out of range"),
            std::string::npos);
  EXPECT_NE(message("negative.obj", square + "f -4294967296 2 3\n").find("out of range"),
            std::string::npos);
  EXPECT_NE(message("wrap.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 4294967296\n")
                .find("out of range"),
            std::string::npos);
  EXPECT_NE(message("huge.off", "OFF\n2147483648 1 0\n0 0 0\n").find("more than the file"),
            std::string::npos);
  EXPECT_NE(message("huge.ply",
                    "ply\nformat ascii 1.0\nelement vertex 100000000000000000\n"
                    "property float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n")
                .find("more than the"),
            std::string::npos);
  const std::string header =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
      "property float y\nproperty float z\n";
  const std::string vertices = "0 0 0\n1 0 0\n0 1 0\n";
  // No properties: nothing to read, however many items (the reader looped 2^63 times).
  const MeshFile empty = read_mesh_file(
      write_file("empty-element.ply", header +
                                          "element nothing 9223372036854775807\n"
                                          "element face 1\nproperty list uchar int vertex_indices\n"
                                          "end_header\n" +
                                          vertices + "3 0 1 2\n"));
  EXPECT_EQ(empty.triangles.size(), 1u);
  // Other lists of the face element (MeshLab's wedge texcoord, ricci-flow's own result) are read
  // past, whatever their values: only the vertex indices must be integers.
  const MeshFile textured = read_mesh_file(
      write_file("texcoord.ply", header +
                                     "element face 1\nproperty list uchar int vertex_indices\n"
                                     "property list uchar float texcoord\nend_header\n" +
                                     vertices + "3 0 1 2 6 0.25 0.5 0.75 0.1 0.2 0.3\n"));
  EXPECT_EQ(textured.triangles.size(), 1u);
  // A binary STL whose header starts with "solid" and whose count is wrong.
  std::string stl = "solid binary" + std::string(68, ' ');
  put<std::uint32_t>(stl, 3);
  stl += std::string(50, '\0');
  EXPECT_NE(message("wrong-count.stl", stl).find("count of 3 triangles needs 234 bytes"),
            std::string::npos)
      << message("wrong-count.stl", stl);
  for (const char* index : {"1e30", "nan", "inf", "0.5", "4294967296"}) {
    const std::string faces =
        "element face 1\nproperty list uchar float vertex_indices\n"
        "end_header\n" +
        vertices + "3 0 1 " + std::string(index) + "\n";
    EXPECT_NE(message("float-index.ply", header + faces).find("is not an integer index"),
              std::string::npos)
        << index;
    // The data's errors name the byte where reading stopped.
    EXPECT_NE(message("float-index.ply", header + faces).find("float-index.ply', byte "),
              std::string::npos)
        << message("float-index.ply", header + faces);
  }
}

}  // namespace
}  // namespace ricci

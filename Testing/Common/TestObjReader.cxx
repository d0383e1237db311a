// SPDX-License-Identifier: GPL-3.0-or-later
// OBJ + MTL reader: a round trip through files in a temporary folder, every
// supported syntax from strings, one check per error case (file:line and
// what), and every truncation of a valid file (parsed or rejected, never a
// crash). Optional argument: the folder holding Testing/Data/Scenes/box.obj.
#include "penumbraObjReader.h"
#include "penumbraTesting.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <sstream>

using namespace penumbra;
namespace fs = std::filesystem;

namespace
{

using Files = std::map<std::string, std::string>;

// Strict unless told: the error cases below are strict mode's messages.
Scene Parse(const std::string& obj, const Files& mtls = Files(), bool strict = true,
  std::vector<std::string>* warnings = nullptr)
{
  std::istringstream in(obj);
  ObjReadOptions options;
  options.Strict = strict;
  return ParseObjScene(
    in, "t.obj",
    [&mtls](const std::string& name) {
      const auto found = mtls.find(name);
      std::unique_ptr<std::istream> stream;
      if (found != mtls.end())
      {
        stream = std::make_unique<std::istringstream>(found->second);
      }
      return stream;
    },
    options, warnings);
}

bool Equal(const RGB& a, double r, double g, double b)
{
  return a.R == r && a.G == g && a.B == b;
}

bool Equal(const Vec3& a, double x, double y, double z)
{
  return a.X == x && a.Y == y && a.Z == z;
}

void Write(const fs::path& path, const std::string& text)
{
  fs::create_directories(path.parent_path());
  std::ofstream out(path, std::ios::binary);
  out << text;
}

PENUMBRA_TEST(TestFiles)
{
  // A folder of its own, so that concurrent runs do not share files.
  std::random_device seed;
  const fs::path dir =
    fs::temp_directory_path() / ("penumbra-TestObjReader-" + std::to_string(seed()));
  fs::create_directories(dir);
  // mtllib paths are relative to the OBJ's folder, not the working directory;
  // several names on one line, and a name containing a space.
  Write(dir / "scene" / "box.obj",
    "mtllib mats/a.mtl b.mtl\nmtllib my materials.mtl\n"
    "v 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\nv 0 2 0\n"
    "usemtl white\nf 1 4 3 2\nusemtl lamp\nf 1 2 5\nusemtl spaced\nf 2 3 5\n");
  Write(dir / "scene" / "mats" / "a.mtl", "newmtl white\nKd 0.7 0.6 0.5\n");
  Write(dir / "scene" / "b.mtl", "newmtl lamp\nKd 0.1\nKe 5 4 3\n");
  Write(dir / "scene" / "my materials.mtl", "newmtl spaced\nKd 0.2 0.3 0.4\n");
  const Scene s = ReadObjScene((dir / "scene" / "box.obj").string());
  PENUMBRA_EXPECT(s.Surfaces.size() == 3);
  if (s.Surfaces.size() == 3)
  {
    PENUMBRA_EXPECT(s.Surfaces[0].Vertices.size() == 4);
    PENUMBRA_EXPECT(Equal(s.Surfaces[0].Vertices[1], 0, 0, 1));
    PENUMBRA_EXPECT(Equal(s.Surfaces[0].Reflectance, 0.7, 0.6, 0.5));
    PENUMBRA_EXPECT(s.Surfaces[0].Emission.IsZero());
    PENUMBRA_EXPECT(Equal(s.Surfaces[1].Reflectance, 0.1, 0.1, 0.1));
    PENUMBRA_EXPECT(Equal(s.Surfaces[1].Emission, 5, 4, 3));
    PENUMBRA_EXPECT(Equal(s.Surfaces[1].Vertices[2], 0, 2, 0));
    PENUMBRA_EXPECT(Equal(s.Surfaces[2].Reflectance, 0.2, 0.3, 0.4));
  }

  // File-level errors.
  const std::string missing = (dir / "nothere.obj").string();
  PENUMBRA_EXPECT_THROW(
    ReadObjScene(missing), InputError, "cannot open OBJ file '" + missing + "': no such file");
  PENUMBRA_EXPECT_THROW(ReadObjScene(dir.string()), InputError, "it is a directory");
  ObjReadOptions strict;
  strict.Strict = true;
  Write(dir / "nomtl.obj", "# no library\n\nmtllib gone.mtl\n");
  PENUMBRA_EXPECT_THROW(ReadObjScene((dir / "nomtl.obj").string(), strict), InputError,
    "nomtl.obj:3: cannot open material library 'gone.mtl'");
  Write(dir / "dirmtl.obj", "mtllib scene\n");
  PENUMBRA_EXPECT_THROW(ReadObjScene((dir / "dirmtl.obj").string(), strict), InputError,
    "dirmtl.obj:1: cannot open material library 'scene'");
  // Without strict mode a missing library is a warning naming file and line.
  std::vector<std::string> warnings;
  const Scene lenient = ReadObjScene((dir / "nomtl.obj").string(), ObjReadOptions(), &warnings);
  PENUMBRA_EXPECT(lenient.Surfaces.empty());
  PENUMBRA_EXPECT(warnings.size() == 1 &&
    warnings[0].find("nomtl.obj:3: cannot open material library 'gone.mtl'") !=
      std::string::npos);
  std::error_code ec;
  fs::remove_all(dir, ec);
}

PENUMBRA_TEST(TestSyntax)
{
  const Files mtls = { { "m.mtl",
                         "# materials\r\n"
                         "newmtl red\n"
                         "Ns 10\nKa 0 0 0\nKs 0.5 0.5 0.5\nillum 2\nmap_Kd red.png\n"
                         "Kd 0.6 0.1 0.1\n"
                         "\n"
                         "newmtl light\n"
                         "Kd 0.25\n"
                         "Ke 10 8 6   # warm\n"
                         "newmtl nokd\n"
                         "Ke 1 1 1\n"
                         "newmtl twice\nKd 0.1\n" },
    { "n.mtl", "newmtl twice\nKd 0.3 0.3 0.3\n" } };
  const std::string obj = "# header comment\n"
                          "mtllib m.mtl n.mtl\n"
                          "\n"
                          "v 0 0 0\n"
                          "v 1 0 0 1.0\n"
                          "v 1 1 0 0.5 0.5 0.5\n"
                          "v\t0\t1\t0\t\n"
                          "v +2 0 -0\n"
                          "v 2 1e0 .5  # trailing comment\n"
                          "vt 0 0\nvn 0 0 1\nvp 0.5\no object\ng group a\ns 1\ns off\nl 1 2\np 1\n"
                          "f 1 2 3\n"
                          "usemtl red\n"
                          "f 1/1 2/1 3/1 4/1\n"
                          "f 1//1 2//1 3//1\n"
                          "f 1/1/1 2/1/1 3/1/1\n"
                          "usemtl light\n"
                          "f -4 -3 -2 -1\n"
                          "usemtl nokd\n"
                          "f 1 2 \\\n"
                          "  3 4 \\\n"
                          "  5\n"
                          "usemtl twice\n"
                          "fo 6 5 4";
  const Scene s = Parse(obj, mtls);
  PENUMBRA_EXPECT(s.Surfaces.size() == 7);
  if (s.Surfaces.size() != 7)
  {
    return;
  }
  const std::size_t sizes[7] = { 3, 4, 3, 3, 4, 5, 3 };
  for (int i = 0; i < 7; ++i)
  {
    PENUMBRA_EXPECT(s.Surfaces[i].Vertices.size() == sizes[i]);
  }
  // Default material before any usemtl; missing Ke means no emission.
  PENUMBRA_EXPECT(Equal(s.Surfaces[0].Reflectance, 0.5, 0.5, 0.5));
  PENUMBRA_EXPECT(s.Surfaces[0].Emission.IsZero());
  PENUMBRA_EXPECT(Equal(s.Surfaces[0].Vertices[2], 1, 1, 0));
  for (int i = 1; i <= 3; ++i)
  {
    PENUMBRA_EXPECT(Equal(s.Surfaces[i].Reflectance, 0.6, 0.1, 0.1));
    PENUMBRA_EXPECT(s.Surfaces[i].Emission.IsZero());
  }
  PENUMBRA_EXPECT(Equal(s.Surfaces[1].Vertices[3], 0, 1, 0));
  // Relative indices -4..-1 are vertices 3..6 (six vertices so far).
  PENUMBRA_EXPECT(Equal(s.Surfaces[4].Vertices[0], 1, 1, 0));
  PENUMBRA_EXPECT(Equal(s.Surfaces[4].Vertices[2], 2, 0, 0));
  PENUMBRA_EXPECT(Equal(s.Surfaces[4].Vertices[3], 2, 1, 0.5));
  PENUMBRA_EXPECT(Equal(s.Surfaces[4].Reflectance, 0.25, 0.25, 0.25));
  PENUMBRA_EXPECT(Equal(s.Surfaces[4].Emission, 10, 8, 6));
  // Missing Kd: the documented default grey.
  PENUMBRA_EXPECT(Equal(s.Surfaces[5].Reflectance, ObjDefaultReflectance, ObjDefaultReflectance,
    ObjDefaultReflectance));
  PENUMBRA_EXPECT(Equal(s.Surfaces[5].Emission, 1, 1, 1));
  PENUMBRA_EXPECT(Equal(s.Surfaces[5].Vertices[4], 2, 0, 0));
  // Redefined material: the last definition wins. Last line without "\n".
  PENUMBRA_EXPECT(Equal(s.Surfaces[6].Reflectance, 0.3, 0.3, 0.3));
  PENUMBRA_EXPECT(Equal(s.Surfaces[6].Vertices[0], 2, 1, 0.5));

  // CRLF line ends, a final line without end of line, a number cut after
  // its decimal point (still a number).
  const Scene crlf = Parse("v 0 0 0\r\nv 1 0 0\r\n\r\nv 0 1 3.\r\nf 1 2 3");
  PENUMBRA_EXPECT(crlf.Surfaces.size() == 1);
  PENUMBRA_EXPECT(crlf.Surfaces.size() == 1 && Equal(crlf.Surfaces[0].Vertices[2], 0, 1, 3));
  // Empty input: an empty scene (ValidateScene and the filters decide).
  PENUMBRA_EXPECT(Parse("").Surfaces.empty());
  PENUMBRA_EXPECT(Parse("# only a comment\n\n").Surfaces.empty());
}

// Expect that parsing OBJ text (or, for MTL, an OBJ naming only m.mtl with
// this text) throws InputError whose message contains `fragment`.
#define EXPECT_PARSE_ERROR(text, fragment) PENUMBRA_EXPECT_THROW(Parse(text), InputError, fragment)
#define EXPECT_MTL_ERROR(text, fragment)                                                           \
  PENUMBRA_EXPECT_THROW(Parse("mtllib m.mtl\n", { { "m.mtl", text } }), InputError, fragment)

PENUMBRA_TEST(TestErrors)
{
  const std::string square = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";
  const std::string eight = square + "v 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n";
  // Coordinates.
  EXPECT_PARSE_ERROR("v 1 a 3", "t.obj:1: y coordinate 'a' is not a number");
  EXPECT_PARSE_ERROR("\nv 1 2", "t.obj:2: vertex has 2 values");
  EXPECT_PARSE_ERROR("v", "t.obj:1: vertex has 0 values");
  EXPECT_PARSE_ERROR("v 1 2 3 4 5", "t.obj:1: vertex has 5 values");
  EXPECT_PARSE_ERROR("v 1 2 3 x", "t.obj:1: w 'x' is not a number");
  EXPECT_PARSE_ERROR("v 1 inf 0", "t.obj:1: y coordinate 'inf' is not finite");
  EXPECT_PARSE_ERROR("v nan 0 0", "t.obj:1: x coordinate 'nan' is not finite");
  EXPECT_PARSE_ERROR("v 0 0 -Infinity", "z coordinate '-Infinity' is not finite");
  EXPECT_PARSE_ERROR("v 1e999 0 0", "t.obj:1: x coordinate '1e999' is out of range");
  EXPECT_PARSE_ERROR("v 0 -1e400 0", "y coordinate '-1e400' is out of range");
  EXPECT_PARSE_ERROR("v 0 0 0x10", "z coordinate '0x10' is not a number");
  EXPECT_PARSE_ERROR("v 0 0 +-1", "z coordinate '+-1' is not a number");
  EXPECT_PARSE_ERROR("v 0 0 1,5", "z coordinate '1,5' is not a number");
  // Truncated last lines: rejected cleanly.
  EXPECT_PARSE_ERROR(square + "v 0.5 0.", "t.obj:5: vertex has 2 values");
  EXPECT_PARSE_ERROR(square + "v 1 2 3e", "t.obj:5: z coordinate '3e' is not a number");
  EXPECT_PARSE_ERROR(square + "f 1 2 3/", "t.obj:5: malformed face vertex '3/'");
  EXPECT_PARSE_ERROR(square + "v 1 2 \\", "t.obj:5: vertex has 2 values");
  // Faces.
  EXPECT_PARSE_ERROR(square + "f 1 2", "t.obj:5: face with 2 vertices (needs at least 3)");
  EXPECT_PARSE_ERROR(square + "f 1 \\\n 2\n", "t.obj:5: face with 2 vertices");
  EXPECT_PARSE_ERROR(square + "f 0 1 2", "t.obj:5: face index 0 is invalid");
  EXPECT_PARSE_ERROR(eight + "f 1 2 9", "t.obj:9: face index 9 out of range (8 vertices)");
  EXPECT_PARSE_ERROR(eight + "f -9 1 2", "t.obj:9: face index -9 out of range (8 vertices)");
  EXPECT_PARSE_ERROR("f 1 2 3\n" + square, "t.obj:1: face index 1 out of range (0 vertices)");
  EXPECT_PARSE_ERROR(square + "f 1 2 99999999999999999999",
    "t.obj:5: face index '99999999999999999999' out of range (4 vertices)");
  EXPECT_PARSE_ERROR(square + "f 1 2/x 3", "t.obj:5: malformed face vertex '2/x'");
  EXPECT_PARSE_ERROR(square + "f 1 2 3/1/1/1", "malformed face vertex '3/1/1/1'");
  EXPECT_PARSE_ERROR(square + "f 1 a 3", "malformed face vertex 'a'");
  EXPECT_PARSE_ERROR(square + "f 1 2 1.5", "malformed face vertex '1.5'");
  EXPECT_PARSE_ERROR(square + "f 1 2 3//", "malformed face vertex '3//'");
  // Statements and materials.
  EXPECT_PARSE_ERROR("ply\nformat ascii 1.0\n", "t.obj:1: unknown statement 'ply'");
  EXPECT_PARSE_ERROR(std::string("v 0 0 0\n\x7f" "ELF\x01\x00\x02", 15),
    "t.obj:2: unknown statement '?ELF");
  EXPECT_PARSE_ERROR("usemtl nothere", "t.obj:1: unknown material 'nothere'");
  EXPECT_PARSE_ERROR("usemtl", "t.obj:1: usemtl without a material name");
  EXPECT_PARSE_ERROR("\n\nmtllib missing.mtl",
    "t.obj:3: cannot open material library 'missing.mtl'");
  EXPECT_PARSE_ERROR("mtllib", "t.obj:1: mtllib without a file name");
  EXPECT_MTL_ERROR("newmtl a\nKd 0.5 0.5",
    "m.mtl:2: malformed Kd: expected 1 or 3 numbers, got 2");
  EXPECT_MTL_ERROR("newmtl a\nKe", "m.mtl:2: malformed Ke: expected 1 or 3 numbers, got 0");
  EXPECT_MTL_ERROR("newmtl a\n\nKd 0.5 x 0.5", "m.mtl:3: Kd green 'x' is not a number");
  EXPECT_MTL_ERROR("newmtl a\nKd 0.5\nKe inf 0 0", "m.mtl:3: Ke red 'inf' is not finite");
  EXPECT_MTL_ERROR("newmtl a\nKe 1e999", "m.mtl:2: Ke '1e999' is out of range");
  EXPECT_MTL_ERROR("newmtl a\nKd xyz 0.1 0.2 0.3", "m.mtl:2: malformed Kd: 'xyz' colours");
  EXPECT_MTL_ERROR("newmtl a\nKd spectral a.rfl 1.0",
    "m.mtl:2: malformed Kd: 'spectral' colours are not supported");
  EXPECT_MTL_ERROR("Kd 1 1 1", "m.mtl:1: Kd before any newmtl");
  EXPECT_MTL_ERROR("newmtl", "m.mtl:1: newmtl without a material name");
  // Absurdly long lines, also when built from continuations.
  const std::string huge(ObjMaxLineLength + 10, '1');
  EXPECT_PARSE_ERROR("v 0 0 0\nv " + huge + " 0 0\n",
    "t.obj:2: line longer than 1048576 characters");
  std::string pieces;
  for (int i = 0; i < 3000; ++i)
  {
    pieces += std::string(500, ' ') + "\\\n";
  }
  EXPECT_PARSE_ERROR("v 0 0 0\n" + pieces, "line longer than 1048576 characters");
  // A number too long for any double is still just a number that overflows.
  EXPECT_PARSE_ERROR("v 0 0 " + std::string(400, '9'), "is out of range");
  // A stream that cannot be read at all.
  std::istringstream failed("v 0 0 0");
  failed.setstate(std::ios::failbit);
  PENUMBRA_EXPECT_THROW(
    ParseObjScene(failed, "t.obj", nullptr), InputError, "cannot read OBJ 't.obj'");
}

// Every prefix of a valid file (a truncated download) and random byte
// corruptions are either parsed or rejected with InputError.
// Real exports name materials that are not defined, or defined with other
// case or spacing: without strict mode they solve, with one warning per name.
PENUMBRA_TEST(TestLenientMaterials)
{
  const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  const Files mtls = { { "m.mtl", "newmtl Wall White\nKd 0.7\nnewmtl lamp\nKe 3\n" } };
  std::vector<std::string> warnings;
  const Scene s = Parse("mtllib m.mtl\nmtllib gone.mtl\n" + tri +
      "usemtl wall  white\nf 1 2 3\nusemtl chrome\nf 1 2 3\nf 3 2 1\nusemtl lamp\nf 1 2 3\n",
    mtls, false, &warnings);
  PENUMBRA_EXPECT(s.Surfaces.size() == 4);
  if (s.Surfaces.size() == 4)
  {
    PENUMBRA_EXPECT(Equal(s.Surfaces[0].Reflectance, 0.7, 0.7, 0.7));
    PENUMBRA_EXPECT(Equal(s.Surfaces[1].Reflectance, ObjDefaultReflectance,
      ObjDefaultReflectance, ObjDefaultReflectance));
    PENUMBRA_EXPECT(s.Surfaces[2].Emission.IsZero());
    PENUMBRA_EXPECT(Equal(s.Surfaces[3].Emission, 3, 3, 3));
  }
  const auto has = [&warnings](const std::string& fragment) {
    int count = 0;
    for (const std::string& w : warnings)
    {
      count += w.find(fragment) != std::string::npos;
    }
    return count == 1;
  };
  PENUMBRA_EXPECT(warnings.size() == 3);
  PENUMBRA_EXPECT(has("t.obj:2: cannot open material library 'gone.mtl'"));
  PENUMBRA_EXPECT(has("material 'wall white' is not defined; used 'Wall White'"));
  PENUMBRA_EXPECT(has("2 faces use material 'chrome', which no material library defines"));
  // Strict mode keeps the errors.
  PENUMBRA_EXPECT_THROW(
    Parse("mtllib m.mtl\n" + tri + "usemtl wall white\nf 1 2 3\n", mtls), InputError,
    "t.obj:5: unknown material 'wall white'");
}

PENUMBRA_TEST(TestTruncationAndCorruption)
{
  const Files mtls = { { "m.mtl", "newmtl a\nKd 0.5 0.25 0.125\nKe 1 2 3\n" } };
  const std::string obj = "mtllib m.mtl\nv 0 0 0\nv 1.5 0 0\nv 1.5 -1e-3 2.25\n"
                          "vn 0 1 0\nusemtl a\nf 1//1 2//1 3//1\nf -3 \\\n -2 -1\n";
  int parsed = 0, rejected = 0, other = 0;
  const auto attempt = [&](const std::string& text) {
    try
    {
      Parse(text, mtls);
      ++parsed;
    }
    catch (const InputError&)
    {
      ++rejected;
    }
    catch (...)
    {
      ++other;
    }
  };
  for (std::size_t n = 0; n <= obj.size(); ++n)
  {
    attempt(obj.substr(0, n));
  }
  std::mt19937 random(12345);
  for (int i = 0; i < 2000; ++i)
  {
    std::string text = obj;
    for (int k = 0; k < 3; ++k)
    {
      text[random() % text.size()] = static_cast<char>(random() % 256);
    }
    attempt(text);
  }
  PENUMBRA_EXPECT(other == 0);
  PENUMBRA_EXPECT(parsed > 0 && rejected > 0);
}

// The OBJ scene of Testing/Data, found through PENUMBRA_TEST_DATA_DIR (CTest
// sets it); without it the case checks nothing.
PENUMBRA_TEST(TestDataScene)
{
  const char* data = std::getenv("PENUMBRA_TEST_DATA_DIR");
  if (!data)
  {
    std::cout << "TestDataScene: PENUMBRA_TEST_DATA_DIR not set, skipped" << std::endl;
    return;
  }
  const fs::path dataDir = data;
  const Scene s = ReadObjScene((dataDir / "Scenes" / "box.obj").string());
  PENUMBRA_EXPECT(s.Surfaces.size() == 7);
  bool valid = true;
  try
  {
    ValidateScene(s);
  }
  catch (const InputError& e)
  {
    valid = false;
    std::cerr << e.what() << std::endl;
  }
  PENUMBRA_EXPECT(valid);
  int emitters = 0;
  for (const Surface& surface : s.Surfaces)
  {
    emitters += !surface.Emission.IsZero();
  }
  PENUMBRA_EXPECT(emitters == 1);
  if (s.Surfaces.size() == 7)
  {
    PENUMBRA_EXPECT_NEAR(ComputePolygonGeometry(s.Surfaces[0].Vertices).Normal.Y, 1.0, 1e-15);
    PENUMBRA_EXPECT_NEAR(ComputePolygonGeometry(s.Surfaces[1].Vertices).Normal.Y, -1.0, 1e-15);
    // Box faces point away from the box centre.
    const Vec3 centre(0.35, 0.3, -0.25);
    for (std::size_t i = 2; i < 7; ++i)
    {
      const PolygonGeometry g = ComputePolygonGeometry(s.Surfaces[i].Vertices);
      PENUMBRA_EXPECT(Dot(g.Normal, g.Centroid - centre) > 0.2);
    }
  }
}

} // namespace

// SPDX-License-Identifier: GPL-3.0-or-later
#include "penumbraObjReader.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <exception>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <system_error>
#include <vector>

namespace penumbra
{

namespace
{

struct Material
{
  RGB Reflectance{ ObjDefaultReflectance, ObjDefaultReflectance, ObjDefaultReflectance };
  RGB Emission;
};

// A token as shown in messages: quoted, control bytes (from a binary file)
// shown as '?', and cut short so that a huge token cannot make a huge message.
std::string Quote(const std::string& token)
{
  std::string shown = token.size() > 40 ? token.substr(0, 40) + "..." : token;
  for (char& c : shown)
  {
    c = (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) ? '?' : c;
  }
  return "'" + shown + "'";
}

// Reads logical lines (backslash continuations joined, comments removed) split
// into whitespace-separated tokens, and formats "name:line: what" errors.
class LineReader
{
public:
  LineReader(std::istream& in, const std::string& name)
    : In(in)
    , Name(name)
  {
  }

  /// The first physical line of the current logical line.
  long long GetLine() const { return this->Line; }

  [[noreturn]] void Fail(const std::string& what) const
  {
    throw InputError(this->Name + ":" + std::to_string(this->Line) + ": " + what);
  }

  bool Next(std::vector<std::string>& tokens)
  {
    tokens.clear();
    std::string line;
    bool started = false;
    while (this->ReadPhysical(line))
    {
      if (!started)
      {
        started = true;
        this->Line = this->Physical;
      }
      if (line.empty() || line.back() != '\\')
      {
        break;
      }
      line.back() = ' ';
    }
    if (this->In.bad())
    {
      this->Fail("read error");
    }
    if (!started)
    {
      return false;
    }
    line.erase(std::min(line.find('#'), line.size()));
    std::size_t i = 0;
    while (i < line.size())
    {
      const std::size_t begin = line.find_first_not_of(" \t\r\f\v", i);
      if (begin == std::string::npos)
      {
        break;
      }
      i = std::min(line.find_first_of(" \t\r\f\v", begin), line.size());
      tokens.push_back(line.substr(begin, i - begin));
    }
    return true;
  }

private:
  // Appends the next physical line (without its end of line) to `line`;
  // false at the end of the stream. Reads byte by byte through the buffer so
  // that an absurdly long line is rejected before it is read whole.
  bool ReadPhysical(std::string& line)
  {
    std::streambuf* buffer = this->In.rdbuf();
    if (!buffer || !this->In.good())
    {
      return false;
    }
    bool any = false;
    for (;;)
    {
      int c = 0;
      try
      {
        c = buffer->sbumpc();
      }
      catch (const std::exception&)
      {
        // libstdc++'s filebuf throws on a failed read (EIO, EISDIR).
        this->Line = this->Physical + 1;
        this->Fail("read error");
      }
      if (c == std::char_traits<char>::eof())
      {
        this->In.setstate(std::ios::eofbit);
        break;
      }
      any = true;
      if (c == '\n')
      {
        break;
      }
      if (line.size() >= ObjMaxLineLength)
      {
        this->Line = this->Physical + 1;
        this->Fail("line longer than " + std::to_string(ObjMaxLineLength) + " characters");
      }
      line.push_back(static_cast<char>(c));
    }
    if (!any)
    {
      return false;
    }
    ++this->Physical;
    if (!line.empty() && line.back() == '\r')
    {
      line.pop_back();
    }
    return true;
  }

  std::istream& In;
  std::string Name;
  long long Physical = 0; // physical lines read
  long long Line = 0;     // first physical line of the current logical line
};

// A finite number; `what` names it in messages ("y coordinate").
double ParseNumber(const LineReader& reader, const std::string& token, const std::string& what)
{
  // from_chars is locale-independent, unlike strtod, but rejects a leading '+'.
  const char* first = token.data();
  const char* last = first + token.size();
  const bool plus = first != last && *first == '+';
  first += plus ? 1 : 0;
  double value = 0.0;
  const std::from_chars_result r = std::from_chars(first, last, value);
  if (r.ec == std::errc::result_out_of_range)
  {
    reader.Fail(what + " " + Quote(token) + " is out of range");
  }
  if (r.ec != std::errc() || r.ptr != last || (plus && *first == '-'))
  {
    reader.Fail(what + " " + Quote(token) + " is not a number");
  }
  if (!std::isfinite(value))
  {
    reader.Fail(what + " " + Quote(token) + " is not finite");
  }
  return value;
}

// Whether `text` is a (signed) decimal integer; stores it in `value`.
bool ParseInteger(const std::string& text, long long& value, bool& overflow)
{
  const char* first = text.data();
  const char* last = first + text.size();
  const std::from_chars_result r = std::from_chars(first, last, value);
  overflow = r.ec == std::errc::result_out_of_range;
  return !text.empty() && r.ptr == last && (r.ec == std::errc() || overflow);
}

// Index into `count` vertices of one face vertex token `i[/t][/n]`.
std::size_t ParseFaceVertex(const LineReader& reader, const std::string& token, std::size_t count)
{
  std::vector<std::string> parts(1);
  for (char c : token)
  {
    if (c == '/')
    {
      parts.emplace_back();
    }
    else
    {
      parts.back().push_back(c);
    }
  }
  long long index = 0, other = 0;
  bool overflow = false, otherOverflow = false;
  const bool ok = parts.size() <= 3 && ParseInteger(parts[0], index, overflow) &&
    (parts.size() < 2 || ParseInteger(parts[1], other, otherOverflow) ||
      (parts.size() == 3 && parts[1].empty())) &&
    (parts.size() < 3 || ParseInteger(parts[2], other, otherOverflow));
  if (!ok)
  {
    reader.Fail("malformed face vertex " + Quote(token) + " (expected i, i/t, i//n or i/t/n)");
  }
  const std::string range = " out of range (" + std::to_string(count) + " vertices)";
  if (overflow)
  {
    reader.Fail("face index " + Quote(parts[0]) + range);
  }
  if (index == 0)
  {
    reader.Fail("face index 0 is invalid (OBJ indices start at 1)");
  }
  const long long n = static_cast<long long>(count);
  if (index > n || index < -n)
  {
    reader.Fail("face index " + std::to_string(index) + range);
  }
  return static_cast<std::size_t>(index > 0 ? index - 1 : n + index);
}

RGB ParseColor(const LineReader& reader, const std::vector<std::string>& t)
{
  const std::string& key = t[0];
  if (t.size() > 1 && (t[1] == "spectral" || t[1] == "xyz"))
  {
    reader.Fail(
      "malformed " + key + ": '" + t[1] + "' colours are not supported (use 1 or 3 numbers)");
  }
  if (t.size() != 2 && t.size() != 4)
  {
    reader.Fail(
      "malformed " + key + ": expected 1 or 3 numbers, got " + std::to_string(t.size() - 1));
  }
  const char* channels[3] = { " red", " green", " blue" };
  RGB c;
  for (int k = 0; k < 3; ++k)
  {
    c[k] = t.size() == 2 ? ParseNumber(reader, t[1], key)
                         : ParseNumber(reader, t[k + 1], key + channels[k]);
  }
  return c;
}

std::string JoinFrom(const std::vector<std::string>& t, std::size_t first)
{
  std::string s;
  for (std::size_t i = first; i < t.size(); ++i)
  {
    s += (i > first ? " " : "") + t[i];
  }
  return s;
}

void ParseMtl(std::istream& in, const std::string& name, std::map<std::string, Material>& materials)
{
  LineReader reader(in, name);
  Material* current = nullptr;
  std::vector<std::string> t;
  while (reader.Next(t))
  {
    if (t.empty())
    {
      continue;
    }
    if (t[0] == "newmtl")
    {
      if (t.size() < 2)
      {
        reader.Fail("newmtl without a material name");
      }
      current = &(materials[JoinFrom(t, 1)] = Material());
    }
    else if (t[0] == "Kd" || t[0] == "Ke")
    {
      if (!current)
      {
        reader.Fail(t[0] + " before any newmtl");
      }
      (t[0] == "Kd" ? current->Reflectance : current->Emission) = ParseColor(reader, t);
    }
  }
}

bool IsIgnoredObjStatement(const std::string& key)
{
  static const char* const ignored[] = { "vt", "vn", "vp", "o", "g", "s", "l", "p", "mg",
    "cstype", "deg", "bmat", "step", "curv", "curv2", "surf", "parm", "trim", "hole", "scrv",
    "sp", "end", "con", "bevel", "c_interp", "d_interp", "lod", "usemap", "maplib",
    "shadow_obj", "trace_obj", "ctech", "stech", "call", "csh" };
  for (const char* k : ignored)
  {
    if (key == k)
    {
      return true;
    }
  }
  return false;
}

// A material name as compared when the exact name is not defined: lower case,
// outer spaces trimmed, inner runs of spaces as one.
std::string LooseName(const std::string& name)
{
  std::string out;
  for (char c : name)
  {
    const bool space = c == ' ' || c == '\t';
    if (space && (out.empty() || out.back() == ' '))
    {
      continue;
    }
    out += space ? ' ' : static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  }
  while (!out.empty() && out.back() == ' ')
  {
    out.pop_back();
  }
  return out;
}

} // namespace

Scene ParseObjScene(std::istream& obj, const std::string& objName, const ObjMaterialOpener& openMtl,
  const ObjReadOptions& options, std::vector<std::string>* warnings)
{
  const auto warn = [warnings](const std::string& line) {
    if (warnings)
    {
      warnings->push_back(line);
    }
  };
  std::map<std::string, std::size_t> undefinedUses; // material name -> faces
  std::map<std::string, std::string> looseMatches;  // used name -> defined name
  std::string undefined;                            // the current material, if undefined
  if (!obj)
  {
    throw InputError("cannot read OBJ '" + objName + "'");
  }
  LineReader reader(obj, objName);
  std::vector<Vec3> vertices;
  std::map<std::string, Material> materials;
  Material current;
  Scene scene;
  std::vector<std::string> t;
  while (reader.Next(t))
  {
    if (t.empty())
    {
      continue;
    }
    const std::string& key = t[0];
    if (key == "v")
    {
      const std::size_t n = t.size() - 1;
      if (n != 3 && n != 4 && n != 6)
      {
        reader.Fail("vertex has " + std::to_string(n) +
          " values (expected x y z [w], or x y z r g b)");
      }
      const char* names[6] = { "x coordinate", "y coordinate", "z coordinate",
        n == 4 ? "w" : "vertex colour", "vertex colour", "vertex colour" };
      double value[6];
      for (std::size_t k = 0; k < n; ++k)
      {
        value[k] = ParseNumber(reader, t[k + 1], names[k]);
      }
      vertices.emplace_back(value[0], value[1], value[2]);
    }
    else if (key == "f" || key == "fo")
    {
      if (t.size() < 4)
      {
        reader.Fail("face with " + std::to_string(t.size() - 1) +
          " vertices (needs at least 3)");
      }
      Surface s{ {}, current.Reflectance, current.Emission };
      for (std::size_t k = 1; k < t.size(); ++k)
      {
        s.Vertices.push_back(vertices[ParseFaceVertex(reader, t[k], vertices.size())]);
      }
      scene.Surfaces.push_back(std::move(s));
      if (!undefined.empty())
      {
        ++undefinedUses[undefined];
      }
    }
    else if (key == "mtllib")
    {
      if (t.size() < 2)
      {
        reader.Fail("mtllib without a file name");
      }
      std::vector<std::string> names(t.begin() + 1, t.end());
      // Exporters write names with spaces unquoted: try the whole rest first.
      std::unique_ptr<std::istream> whole;
      if (names.size() > 1 && openMtl && (whole = openMtl(JoinFrom(t, 1))))
      {
        ParseMtl(*whole, JoinFrom(t, 1), materials);
        continue;
      }
      for (const std::string& name : names)
      {
        std::unique_ptr<std::istream> in = openMtl ? openMtl(name) : nullptr;
        if (!in || !*in)
        {
          if (options.Strict)
          {
            reader.Fail("cannot open material library " + Quote(name));
          }
          warn(objName + ":" + std::to_string(reader.GetLine()) +
            ": cannot open material library " + Quote(name) +
            ": the faces using its materials get the default material");
          continue;
        }
        ParseMtl(*in, name, materials);
      }
    }
    else if (key == "usemtl")
    {
      if (t.size() < 2)
      {
        reader.Fail("usemtl without a material name");
      }
      const std::string name = JoinFrom(t, 1);
      auto found = materials.find(name);
      undefined.clear();
      if (found == materials.end() && !options.Strict)
      {
        // Exporters and hand edits disagree on case and spacing.
        const std::string loose = LooseName(name);
        found = std::find_if(materials.begin(), materials.end(),
          [&loose](const auto& m) { return LooseName(m.first) == loose; });
        if (found != materials.end())
        {
          looseMatches.emplace(name, found->first);
        }
      }
      if (found != materials.end())
      {
        current = found->second;
      }
      else if (options.Strict)
      {
        reader.Fail("unknown material " + Quote(name));
      }
      else
      {
        current = Material();
        undefined = name;
      }
    }
    else if (!IsIgnoredObjStatement(key))
    {
      reader.Fail("unknown statement " + Quote(key));
    }
  }
  for (const auto& match : looseMatches)
  {
    warn(objName + ": material " + Quote(match.first) + " is not defined; used " +
      Quote(match.second) + ", which differs only in case or spacing");
  }
  for (const auto& use : undefinedUses)
  {
    std::ostringstream os;
    os << objName << ": " << use.second << (use.second == 1 ? " face uses" : " faces use")
       << " material " << Quote(use.first) << ", which no material library defines: given the "
       << "default material (reflectance " << ObjDefaultReflectance << ", no emission)";
    warn(os.str());
  }
  return scene;
}

Scene ReadObjScene(
  const std::string& objPath, const ObjReadOptions& options, std::vector<std::string>* warnings)
{
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_directory(objPath, ec))
  {
    throw InputError("cannot open OBJ file '" + objPath + "': it is a directory");
  }
  std::ifstream in(objPath, std::ios::binary);
  if (!in)
  {
    throw InputError("cannot open OBJ file '" + objPath + "'" +
      (fs::exists(objPath, ec) ? "" : ": no such file"));
  }
  const fs::path folder = fs::path(objPath).parent_path();
  const ObjMaterialOpener open = [&folder](const std::string& name) {
    fs::path path(name);
    if (path.is_relative())
    {
      path = folder / path;
    }
    std::error_code error;
    std::unique_ptr<std::istream> stream;
    if (!fs::is_directory(path, error))
    {
      stream = std::make_unique<std::ifstream>(path, std::ios::binary);
    }
    return stream && *stream ? std::move(stream) : nullptr;
  };
  return ParseObjScene(in, objPath, open, options, warnings);
}

} // namespace penumbra

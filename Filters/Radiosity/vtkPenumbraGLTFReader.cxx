// SPDX-License-Identifier: GPL-3.0-or-later
#include "vtkPenumbraGLTFReader.h"

#include "vtkPenumbraSceneConversion.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCommand.h"
#include "vtkDataArray.h"
#include "vtkGLTFDocumentLoader.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMatrix4x4.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkTriangleStrip.h"

#include "penumbraObjReader.h"
#include "penumbraScene.h"

#include <vtk_jsoncpp.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <memory>
#include <sstream>
#include <vector>

vtkStandardNewMacro(vtkPenumbraGLTFReader);

namespace
{
using Model = vtkGLTFDocumentLoader::Model;

/// Keeps the loader's first error, so that it reaches the user once, with the
/// file name, and its warnings, so that the reader relays those that apply.
class LoaderMessages : public vtkCommand
{
public:
  static LoaderMessages* New() { return new LoaderMessages; }
  void Execute(vtkObject*, unsigned long event, void* callData) override
  {
    const std::string text = callData ? static_cast<const char*>(callData) : "";
    if (event == vtkCommand::WarningEvent)
    {
      // The reader reads this extension itself.
      if (text.find("KHR_materials_emissive_strength") == std::string::npos)
      {
        const std::size_t prefix = text.find("): ");
        this->Warnings.push_back(prefix == std::string::npos ? text : text.substr(prefix + 3));
      }
    }
    else if (this->Error.empty())
    {
      this->Error = vtkPenumbraAlgorithm::ErrorText(text);
    }
  }
  std::string Error;
  std::vector<std::string> Warnings;
};

/// What the loader keeps of the file, and the JSON text it does not keep.
struct GLTFFile
{
  std::string Path;
  Json::Value Document;

  [[noreturn]] void Fail(const std::string& what) const
  {
    throw penumbra::InputError("glTF file '" + this->Path + "': " + what);
  }
};

bool EndsWithGlb(const std::string& path)
{
  return path.size() >= 4 && path.compare(path.size() - 4, 4, ".glb") == 0;
}

std::uint32_t LittleEndian32(const std::string& bytes, std::size_t at)
{
  std::uint32_t value = 0;
  for (int k = 3; k >= 0; --k)
  {
    value = (value << 8) | static_cast<unsigned char>(bytes[at + k]);
  }
  return value;
}

/// The JSON text: the whole .gltf, or a .glb's first chunk (it must be JSON).
std::string JsonText(const GLTFFile& file)
{
  std::ifstream in(file.Path, std::ios::binary);
  if (!in)
  {
    file.Fail("cannot open the file");
  }
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const bool binary = bytes.size() >= 4 && bytes.compare(0, 4, "glTF") == 0;
  if (binary != EndsWithGlb(file.Path))
  {
    file.Fail(binary ? "binary glTF must be named .glb" : "a .glb file must be binary glTF");
  }
  if (!binary)
  {
    return bytes;
  }
  // Header: magic, version, length; then chunks of (length, type, data).
  if (bytes.size() < 20 || LittleEndian32(bytes, 4) != 2 ||
    LittleEndian32(bytes, 16) != 0x4E4F534Au || LittleEndian32(bytes, 12) > bytes.size() - 20)
  {
    file.Fail("not a glTF 2.0 binary file (bad header or JSON chunk)");
  }
  return bytes.substr(20, LittleEndian32(bytes, 12));
}

void ParseJson(GLTFFile& file)
{
  const std::string text = JsonText(file);
  Json::CharReaderBuilder builder;
  std::unique_ptr<Json::CharReader> reader(builder.newCharReader());
  std::string errors;
  if (!reader->parse(text.data(), text.data() + text.size(), &file.Document, &errors) ||
    !file.Document.isObject())
  {
    // jsoncpp's first error: "* Line L, Column C" and its description on the next line.
    std::istringstream lines(errors);
    std::string where, what;
    std::getline(lines, where);
    std::getline(lines, what);
    where = where.substr(std::min<std::size_t>(2, where.size()));
    what = what.substr(std::min(what.find_first_not_of(' '), what.size()));
    file.Fail("not glTF (invalid JSON" + (where.empty() ? "" : " at " + where) +
      (what.empty() ? "" : ": " + what) + ")");
  }
}

/// `value[key]`, or null when `value` is not an object (jsoncpp throws then).
const Json::Value& Member(const Json::Value& value, const char* key)
{
  static const Json::Value null;
  return value.isObject() ? value[key] : null;
}

/// Nodes must form trees (VTK's loader recurses without end on a cycle).
void CheckNodeTrees(const GLTFFile& file)
{
  const Json::Value& nodes = Member(file.Document, "nodes");
  const int count = nodes.isArray() ? static_cast<int>(nodes.size()) : 0;
  std::vector<int> parent(count, -1);
  for (int n = 0; n < count; ++n)
  {
    const Json::Value& children = Member(nodes[n], "children");
    for (Json::ArrayIndex k = 0; children.isArray() && k < children.size(); ++k)
    {
      const int child = children[k].isInt() ? children[k].asInt() : -1;
      if (child < 0 || child >= count)
      {
        file.Fail("node " + std::to_string(n) + ": child index out of range");
      }
      if (child == n)
      {
        file.Fail("node " + std::to_string(n) + " is its own ancestor");
      }
      if (parent[child] >= 0)
      {
        file.Fail("node " + std::to_string(child) + " has more than one parent");
      }
      parent[child] = n;
    }
  }
  // With one parent each, a cycle is a walk up that comes back to where it is.
  enum : char
  {
    Unknown,
    OnWalk,
    InTree
  };
  std::vector<char> state(count, Unknown);
  for (int n = 0; n < count; ++n)
  {
    int up = n;
    for (; up >= 0 && state[up] == Unknown; up = parent[up])
    {
      state[up] = OnWalk;
    }
    if (up >= 0 && state[up] == OnWalk)
    {
      file.Fail("node " + std::to_string(up) + " is its own ancestor");
    }
    for (up = n; up >= 0 && state[up] == OnWalk; up = parent[up])
    {
      state[up] = InTree;
    }
  }
}

/// glTF requires a reader to refuse a file that requires an extension it does not
/// know (compressed meshes, e.g.): those whose loss changes no surface are known.
void CheckRequiredExtensions(const GLTFFile& file)
{
  static const char* const known[] = { "KHR_materials_emissive_strength", "KHR_materials_unlit",
    "KHR_texture_transform", "KHR_lights_punctual" };
  const Json::Value& required = Member(file.Document, "extensionsRequired");
  for (Json::ArrayIndex k = 0; required.isArray() && k < required.size(); ++k)
  {
    const std::string name = required[k].isString() ? required[k].asString() : "";
    if (std::none_of(std::begin(known), std::end(known),
          [&name](const char* extension) { return name == extension; }))
    {
      file.Fail("it requires the extension '" + name + "', which the reader does not read");
    }
  }
}

/// `value[key]` as a non-negative integer, `fallback` when absent.
std::uint64_t Count(
  const GLTFFile& file, const Json::Value& value, const char* key, std::uint64_t fallback)
{
  const Json::Value& member = Member(value, key);
  if (member.isNull())
  {
    return fallback;
  }
  if (!member.isUInt64())
  {
    file.Fail(std::string(key) + " is not a non-negative integer");
  }
  return member.asUInt64();
}

/// Every accessor and buffer view within what it reads from (VTK's loader reads
/// past the end of its buffer otherwise).
void CheckAccessors(const GLTFFile& file)
{
  const Json::Value& buffers = Member(file.Document, "buffers");
  const Json::Value& views = Member(file.Document, "bufferViews");
  const Json::Value& accessors = Member(file.Document, "accessors");
  const std::uint64_t none = ~std::uint64_t(0);
  for (Json::ArrayIndex v = 0; views.isArray() && v < views.size(); ++v)
  {
    const std::string what = "bufferView " + std::to_string(v);
    const std::uint64_t buffer = Count(file, views[v], "buffer", none);
    if (!buffers.isArray() || buffer >= buffers.size())
    {
      file.Fail(what + ": buffer index out of range");
    }
    if (Count(file, views[v], "byteOffset", 0) + Count(file, views[v], "byteLength", none) >
      Count(file, buffers[static_cast<Json::ArrayIndex>(buffer)], "byteLength", 0))
    {
      file.Fail(what + " runs past the end of its buffer");
    }
  }
  const std::map<std::string, int> components = { { "SCALAR", 1 }, { "VEC2", 2 },
    { "VEC3", 3 }, { "VEC4", 4 }, { "MAT2", 4 }, { "MAT3", 9 }, { "MAT4", 16 } };
  const std::map<std::uint64_t, int> sizes = { { 5120, 1 }, { 5121, 1 }, { 5122, 2 },
    { 5123, 2 }, { 5125, 4 }, { 5126, 4 } };
  for (Json::ArrayIndex a = 0; accessors.isArray() && a < accessors.size(); ++a)
  {
    const Json::Value& accessor = accessors[a];
    const std::string what = "accessor " + std::to_string(a);
    const std::uint64_t view = Count(file, accessor, "bufferView", none);
    if (view == none)
    {
      continue; // zeros, or sparse values only
    }
    const Json::Value& type = Member(accessor, "type");
    const auto width = components.find(type.isString() ? type.asString() : "");
    const auto size = sizes.find(Count(file, accessor, "componentType", 0));
    if (width == components.end() || size == sizes.end())
    {
      file.Fail(what + ": unknown type or componentType");
    }
    if (!views.isArray() || view >= views.size())
    {
      file.Fail(what + ": bufferView index out of range");
    }
    const Json::Value& viewValue = views[static_cast<Json::ArrayIndex>(view)];
    const std::uint64_t element = static_cast<std::uint64_t>(width->second * size->second);
    std::uint64_t stride = Count(file, viewValue, "byteStride", 0);
    stride = stride == 0 ? element : stride; // absent or 0: tightly packed, as the loader reads
    const std::uint64_t count = Count(file, accessor, "count", none);
    const std::uint64_t length = Count(file, viewValue, "byteLength", 0);
    const std::uint64_t offset = Count(file, accessor, "byteOffset", 0);
    // (count - 1) stride + element bytes from offset; divided, so a huge count does not wrap.
    const bool fits = count == 0 ||
      (offset <= length && length - offset >= element &&
        count - 1 <= (length - offset - element) / stride);
    if (count == none || !fits)
    {
      file.Fail(what + ": count runs past the end of its bufferView");
    }
  }
}

/// KHR_materials_emissive_strength of material `index`, 1 without it.
double EmissiveStrength(const GLTFFile& file, int index)
{
  const Json::Value& materials = Member(file.Document, "materials");
  if (!materials.isArray() || index < 0 || index >= static_cast<int>(materials.size()))
  {
    return 1.0;
  }
  const Json::Value& extension = Member(
    Member(Member(materials[index], "extensions"), "KHR_materials_emissive_strength"),
    "emissiveStrength");
  if (extension.isNull())
  {
    return 1.0;
  }
  if (!extension.isNumeric())
  {
    file.Fail("material " + std::to_string(index) + ": emissiveStrength is not a number");
  }
  return extension.asDouble();
}

double SrgbToLinear(double c)
{
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

/// Mean linear RGB of an 8-bit sRGB image; false when it has no pixels.
bool MeanTextureColor(vtkImageData* image, double mean[3])
{
  vtkDataArray* pixels = image ? image->GetPointData()->GetScalars() : nullptr;
  if (!pixels || pixels->GetNumberOfTuples() == 0)
  {
    return false;
  }
  const int components = pixels->GetNumberOfComponents();
  const double scale = pixels->GetDataTypeMax() > 0 ? pixels->GetDataTypeMax() : 1.0;
  mean[0] = mean[1] = mean[2] = 0.0;
  for (vtkIdType i = 0; i < pixels->GetNumberOfTuples(); ++i)
  {
    for (int c = 0; c < 3; ++c)
    {
      // Grey (1 or 2 components) repeats its first channel.
      const int source = components >= 3 ? c : 0;
      mean[c] += SrgbToLinear(pixels->GetComponent(i, source) / scale);
    }
  }
  for (int c = 0; c < 3; ++c)
  {
    mean[c] /= static_cast<double>(pixels->GetNumberOfTuples());
  }
  return true;
}

/// Reads the scene out of the loaded model; the reader warns through `owner`.
class SceneBuilder
{
public:
  SceneBuilder(const GLTFFile& file, const Model& model, vtkPenumbraGLTFReader* owner)
    : File(file)
    , TheModel(model)
    , Owner(owner)
    , Materials(model.Materials.size())
    , Known(model.Materials.size(), false)
  {
  }

  penumbra::Scene Build()
  {
    if (this->TheModel.Scenes.empty())
    {
      this->File.Fail("it has no scene");
    }
    const int index = this->TheModel.DefaultScene;
    const auto& scene =
      this->TheModel.Scenes[index >= 0 && index < static_cast<int>(this->TheModel.Scenes.size())
          ? index
          : 0];
    vtkNew<vtkMatrix4x4> identity;
    for (unsigned int node : scene.Nodes)
    {
      this->Visit(static_cast<int>(node), identity);
    }
    if (this->SkippedPrimitives > 0)
    {
      this->Owner->Warn("glTF file '" + this->File.Path + "': skipped " +
        std::to_string(this->SkippedPrimitives) +
        " primitive(s) without triangles (points, lines or no positions); only triangles are "
        "surfaces");
    }
    return std::move(this->Scene);
  }

private:
  struct Material
  {
    penumbra::RGB Reflectance;
    penumbra::RGB Emission;
  };

  /// Adds node `index` and its descendants (CheckNodeTrees made them a tree).
  void Visit(int index, vtkMatrix4x4* parent)
  {
    if (index < 0 || index >= static_cast<int>(this->TheModel.Nodes.size()))
    {
      this->File.Fail("node index " + std::to_string(index) + " out of range");
    }
    const auto& node = this->TheModel.Nodes[index];
    vtkNew<vtkMatrix4x4> global;
    vtkMatrix4x4* local = node.Transform ? node.Transform.Get() : node.Matrix.Get();
    if (local)
    {
      vtkMatrix4x4::Multiply4x4(parent, local, global);
    }
    else
    {
      global->DeepCopy(parent);
    }
    for (int k = 0; k < 16; ++k)
    {
      if (!std::isfinite(global->GetData()[k]))
      {
        this->File.Fail("node " + std::to_string(index) + " has a non-finite transform");
      }
    }
    if (node.Mesh >= 0)
    {
      if (node.Mesh >= static_cast<int>(this->TheModel.Meshes.size()))
      {
        this->File.Fail("node " + std::to_string(index) + ": mesh index out of range");
      }
      const auto& mesh = this->TheModel.Meshes[node.Mesh];
      for (std::size_t p = 0; p < mesh.Primitives.size(); ++p)
      {
        this->AddPrimitive(node.Mesh, p, global);
      }
    }
    for (int child : node.Children)
    {
      this->Visit(child, global);
    }
  }

  void AddPrimitive(int meshIndex, std::size_t index, vtkMatrix4x4* transform)
  {
    const auto& mesh = this->TheModel.Meshes[meshIndex];
    const auto& primitive = mesh.Primitives[index];
    vtkPolyData* geometry = primitive.Geometry;
    const std::string where = "mesh " + std::to_string(meshIndex) +
      (mesh.Name.empty() ? "" : " '" + mesh.Name + "'") + " primitive " + std::to_string(index);
    if (!geometry || !geometry->GetPoints())
    {
      ++this->SkippedPrimitives;
      return;
    }
    if (geometry->GetNumberOfPolys() == 0 && geometry->GetNumberOfStrips() == 0)
    {
      this->SkippedPrimitives += geometry->GetNumberOfCells() > 0 ? 1 : 0;
      return;
    }
    // glTF's front faces are clockwise under a mirroring transform.
    const bool mirrored = transform->Determinant() < 0.0;
    const Material& material = this->MaterialOf(primitive.Material);
    vtkNew<vtkCellArray> triangles;
    triangles->DeepCopy(geometry->GetPolys());
    vtkIdType count;
    const vtkIdType* ids;
    for (auto strips = vtk::TakeSmartPointer(geometry->GetStrips()->NewIterator());
         !strips->IsDoneWithTraversal(); strips->GoToNextCell())
    {
      strips->GetCurrentCell(count, ids);
      vtkTriangleStrip::DecomposeStrip(static_cast<int>(count), ids, triangles);
    }
    vtkPoints* points = geometry->GetPoints();
    for (auto cells = vtk::TakeSmartPointer(triangles->NewIterator());
         !cells->IsDoneWithTraversal(); cells->GoToNextCell())
    {
      cells->GetCurrentCell(count, ids);
      penumbra::Surface surface;
      surface.Reflectance = material.Reflectance;
      surface.Emission = material.Emission;
      for (vtkIdType k = 0; k < count; ++k)
      {
        const vtkIdType id = ids[mirrored ? count - 1 - k : k];
        if (id < 0 || id >= points->GetNumberOfPoints())
        {
          this->File.Fail(where + ": vertex index " + std::to_string(id) + " out of range");
        }
        double local[4] = { 0.0, 0.0, 0.0, 1.0 };
        points->GetPoint(id, local);
        double world[4];
        transform->MultiplyPoint(local, world);
        if (!std::isfinite(world[0]) || !std::isfinite(world[1]) || !std::isfinite(world[2]))
        {
          this->File.Fail(where + ": non-finite vertex coordinate");
        }
        surface.Vertices.push_back({ world[0], world[1], world[2] });
      }
      this->Scene.Surfaces.push_back(std::move(surface));
    }
  }

  const Material& MaterialOf(int index)
  {
    if (index < 0)
    {
      static const Material none{ { penumbra::ObjDefaultReflectance,
                                    penumbra::ObjDefaultReflectance,
                                    penumbra::ObjDefaultReflectance },
        { 0.0, 0.0, 0.0 } };
      return none;
    }
    if (index >= static_cast<int>(this->Materials.size()))
    {
      this->File.Fail("material index " + std::to_string(index) + " out of range");
    }
    if (!this->Known[index])
    {
      this->Materials[index] = this->ReadMaterial(index);
      this->Known[index] = true;
    }
    return this->Materials[index];
  }

  Material ReadMaterial(int index)
  {
    const auto& m = this->TheModel.Materials[index];
    const std::string name = "material " + std::to_string(index) + " '" + m.Name + "'";
    double base[3] = { 1.0, 1.0, 1.0 };
    double emissive[3] = { 0.0, 0.0, 0.0 };
    const auto& baseFactor = m.PbrMetallicRoughness.BaseColorFactor;
    std::copy_n(baseFactor.begin(), std::min<std::size_t>(3, baseFactor.size()), base);
    std::copy_n(m.EmissiveFactor.begin(), std::min<std::size_t>(3, m.EmissiveFactor.size()),
      emissive);
    const int texture = m.PbrMetallicRoughness.BaseColorTexture.Index;
    if (texture >= 0)
    {
      double mean[3];
      const int source = texture < static_cast<int>(this->TheModel.Textures.size())
        ? this->TheModel.Textures[texture].Source
        : -1;
      if (source < 0 || source >= static_cast<int>(this->TheModel.Images.size()) ||
        !MeanTextureColor(this->TheModel.Images[source].ImageData, mean))
      {
        this->File.Fail(name + ": its baseColorTexture has no image that could be read");
      }
      std::transform(base, base + 3, mean, base, std::multiplies<double>());
      this->Owner->Warn("glTF file '" + this->File.Path + "': " + name +
        " has a baseColorTexture; its reflectance is baseColorFactor times the texture's mean "
        "colour (the texture's variation is ignored)");
    }
    if (m.EmissiveTexture.Index >= 0)
    {
      this->Owner->Warn("glTF file '" + this->File.Path + "': " + name +
        " has an emissiveTexture, ignored (emission is emissiveFactor times strength)");
    }
    const double strength = EmissiveStrength(this->File, index);
    Material result{ { base[0], base[1], base[2] },
      { emissive[0] * strength, emissive[1] * strength, emissive[2] * strength } };
    for (double v : { base[0], base[1], base[2], result.Emission.R, result.Emission.G,
           result.Emission.B })
    {
      if (!std::isfinite(v))
      {
        this->File.Fail(name + " has a non-finite colour factor or emissive strength");
      }
    }
    return result;
  }

  const GLTFFile& File;
  const Model& TheModel;
  vtkPenumbraGLTFReader* Owner;
  std::vector<Material> Materials;
  std::vector<bool> Known;
  penumbra::Scene Scene;
  int SkippedPrimitives = 0;
};

/// Load the file with VTK's loader; its first error becomes ours, with the file name.
std::shared_ptr<Model> LoadModel(const GLTFFile& file, vtkPenumbraGLTFReader* owner)
{
  vtkNew<vtkGLTFDocumentLoader> loader;
  vtkNew<LoaderMessages> messages;
  loader->AddObserver(vtkCommand::ErrorEvent, messages);
  loader->AddObserver(vtkCommand::WarningEvent, messages);
  std::vector<char> binary;
  bool ok = false;
  try
  {
    ok = loader->LoadModelMetaDataFromFile(file.Path) &&
      (!EndsWithGlb(file.Path) || loader->LoadFileBuffer(file.Path, binary)) &&
      loader->LoadModelData(binary) && loader->BuildModelVTKGeometry();
  }
  catch (const std::exception& e) // jsoncpp's, on members of the wrong JSON type
  {
    messages->Error = e.what();
  }
  for (const std::string& warning : messages->Warnings)
  {
    owner->Warn("glTF file '" + file.Path + "': " + warning);
  }
  if (!ok || !loader->GetInternalModel())
  {
    file.Fail(
      "VTK's glTF loader failed" + (messages->Error.empty() ? "" : ": " + messages->Error));
  }
  return loader->GetInternalModel();
}
} // namespace

vtkPenumbraGLTFReader::vtkPenumbraGLTFReader()
{
  this->SetNumberOfInputPorts(0);
}

int vtkPenumbraGLTFReader::Execute(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  // vtkPenumbraAlgorithm::RequestData turns what this throws into the error
  // and an empty output.
  if (this->FileName.empty())
  {
    throw penumbra::InputError("FileName is not set");
  }
  GLTFFile file;
  file.Path = this->FileName;
  // Our own parse first: it gives the clearer message for a file that is not
  // glTF, and the loader does not keep KHR_materials_emissive_strength.
  ParseJson(file);
  CheckRequiredExtensions(file);
  CheckNodeTrees(file);
  CheckAccessors(file);
  const std::shared_ptr<Model> model = LoadModel(file, this);
  penumbra::SceneToPolyData(
    SceneBuilder(file, *model, this).Build(), vtkPolyData::GetData(outputVector));
  return 1;
}

void vtkPenumbraGLTFReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << this->FileName << "\n";
}

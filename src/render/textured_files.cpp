#include "ricci/render/textured_files.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <vector>

#include "ricci/errors.hpp"
#include "ricci/mesh/io.hpp"
#include "ricci/render/render_mesh.hpp"

#ifdef RICCI_HAVE_GLTF
// Debian's libtinygltf is a shared library with the implementation inside; the header is used
// for declarations only, without stb (images are embedded as the encoded bytes they are).
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#include <tiny_gltf.h>
#endif

namespace ricci {
namespace fs = std::filesystem;

namespace {

std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot read the texture image");
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

/// "image/png" or "image/jpeg" from the file's first bytes.
std::string image_mime_type(const std::string& bytes, const std::string& where) {
  static const char png[] = "\x89PNG\r\n\x1a\n";
  if (bytes.size() >= 8 && std::memcmp(bytes.data(), png, 8) == 0) return "image/png";
  if (bytes.size() >= 3 && static_cast<unsigned char>(bytes[0]) == 0xFF &&
      static_cast<unsigned char>(bytes[1]) == 0xD8 &&
      static_cast<unsigned char>(bytes[2]) == 0xFF) {
    return "image/jpeg";
  }
  throw InvalidInput(where + ": the texture must be a PNG or JPEG image (glTF embeds no other)");
}

}  // namespace

Image checkerboard_texture(int pixels, int squares) {
  if (pixels < 8 || pixels > 16384 || squares < 1 || squares > pixels) {
    throw InvalidInput("checkerboard_texture: pixels must lie in [8, 16384] and squares in [1, " +
                       std::to_string(pixels) + "]");
  }
  const RenderOptions colours;
  const std::uint32_t light = pack_rgb(colours.checker_light);
  const std::uint32_t dark = pack_rgb(colours.checker_dark);
  // Two kinds of row, the squares' columns starting light or dark: each row is a copy of one.
  std::vector<std::uint32_t> rows[2];
  for (int x = 0; x < pixels; ++x) {
    const int column = static_cast<int>((static_cast<long>(x) * squares) / pixels);
    rows[0].push_back(column & 1 ? dark : light);
    rows[1].push_back(column & 1 ? light : dark);
  }
  Image image;
  image.width = image.height = pixels;
  image.pixels.resize(static_cast<std::size_t>(pixels) * pixels);
  for (int y = 0; y < pixels; ++y) {
    // Row 0 is the top of the image, v = 1: squares counted from v = 0 as render_mesh does.
    const int row = static_cast<int>((static_cast<long>(pixels - 1 - y) * squares) / pixels);
    std::copy(rows[row & 1].begin(), rows[row & 1].end(),
              image.pixels.begin() + static_cast<std::ptrdiff_t>(y) * pixels);
  }
  return image;
}

ObjMaterialFiles write_obj_material(const std::string& obj_path, const std::string& texture_path) {
  const fs::path obj(obj_path);
  fs::path stem = obj;
  stem.replace_extension();
  ObjMaterialFiles files;
  files.mtl = stem.string() + ".mtl";
  files.library = fs::path(files.mtl).filename().string();
  std::string map;  // the texture as the MTL names it
  if (texture_path.empty()) {
    files.texture = stem.string() + ".png";
    write_png(files.texture, checkerboard_texture());
    map = fs::path(files.texture).filename().string();
  } else {
    std::error_code error;
    if (!fs::is_regular_file(texture_path, error)) {
      throw IoError(texture_path + ": no such texture image");
    }
    files.texture = texture_path;
    const fs::path folder = fs::absolute(obj).parent_path();
    map = fs::absolute(texture_path).lexically_normal().lexically_relative(folder).generic_string();
    if (map.empty()) map = fs::absolute(texture_path).string();
  }
  const ObjMaterial material;
  write_file_atomically(files.mtl, [&](std::ostream& out) {
    out << "# ricci: the checkerboard (or --texture) over the texture coordinates\n"
        << "newmtl " << material.name << "\n"
        << "Ka 1 1 1\nKd 1 1 1\nKs 0 0 0\nd 1\nillum 1\n"
        << "map_Kd " << map << "\n";
  });
  return files;
}

TexturedMesh read_glb(const std::string& path) {
#ifndef RICCI_HAVE_GLTF
  throw IoError(path + ": this ricci was built without tinygltf (install libtinygltf-dev)");
#else
  tinygltf::TinyGLTF loader;
  // The texture's bytes are not needed: no image decoder.
  loader.SetImageLoader([](tinygltf::Image*, const int, std::string*, std::string*, int, int,
                           const unsigned char*, int, void*) { return true; },
                        nullptr);
  tinygltf::Model model;
  std::string error, warning;
  if (!loader.LoadBinaryFromFile(&model, &error, &warning, path)) {
    throw IoError(path + ": not a glTF binary file ricci can read: " + error);
  }
  if (model.meshes.empty()) throw InvalidInput(path + ": the glTF file holds no mesh");
  // Reads accessor `a` as doubles (float components) or indices (unsigned integers).
  auto floats = [&](int a, int components) {
    const tinygltf::Accessor& accessor = model.accessors.at(a);
    const tinygltf::BufferView& view = model.bufferViews.at(accessor.bufferView);
    const std::vector<unsigned char>& data = model.buffers.at(view.buffer).data;
    if (accessor.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT) {
      throw InvalidInput(path + ": accessor " + std::to_string(a) + " is not float");
    }
    const std::size_t stride = view.byteStride > 0 ? view.byteStride : 4 * components;
    Eigen::MatrixXd values(static_cast<Eigen::Index>(accessor.count), components);
    for (std::size_t i = 0; i < accessor.count; ++i) {
      const std::size_t at = view.byteOffset + accessor.byteOffset + i * stride;
      if (at + 4 * components > data.size()) throw IoError(path + ": an accessor overruns");
      for (int k = 0; k < components; ++k) {
        float x;
        std::memcpy(&x, data.data() + at + 4 * k, 4);
        values(static_cast<Eigen::Index>(i), k) = x;
      }
    }
    return values;
  };
  auto integers = [&](int a) {
    const tinygltf::Accessor& accessor = model.accessors.at(a);
    const tinygltf::BufferView& view = model.bufferViews.at(accessor.bufferView);
    const std::vector<unsigned char>& data = model.buffers.at(view.buffer).data;
    const int size = accessor.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT     ? 4
                     : accessor.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ? 2
                     : accessor.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE  ? 1
                                                                                        : 0;
    if (size == 0) throw InvalidInput(path + ": indices must be unsigned integers");
    std::vector<long> values(accessor.count);
    for (std::size_t i = 0; i < accessor.count; ++i) {
      const std::size_t at = view.byteOffset + accessor.byteOffset + i * size;
      if (at + size > data.size()) throw IoError(path + ": an accessor overruns");
      std::uint32_t x = 0;
      std::memcpy(&x, data.data() + at, size);  // little endian, as glTF is
      values[i] = x;
    }
    return values;
  };
  TexturedMesh result;
  std::vector<Eigen::Vector3d> positions;
  std::vector<Eigen::Vector2d> uvs;
  std::vector<std::array<int, 3> > faces, uv_faces;
  std::map<std::array<double, 3>, int> welded;
  for (const tinygltf::Primitive& p : model.meshes.front().primitives) {
    if (p.mode != TINYGLTF_MODE_TRIANGLES && p.mode != -1) continue;
    if (!p.attributes.count("POSITION") || !p.attributes.count("TEXCOORD_0")) {
      throw InvalidInput(path + ": a primitive has no POSITION or no TEXCOORD_0");
    }
    const Eigen::MatrixXd xyz = floats(p.attributes.at("POSITION"), 3);
    const Eigen::MatrixXd st = floats(p.attributes.at("TEXCOORD_0"), 2);
    if (st.rows() != xyz.rows()) throw InvalidInput(path + ": TEXCOORD_0 and POSITION differ");
    std::vector<int> vertex(static_cast<std::size_t>(xyz.rows()));
    const int uv_base = static_cast<int>(uvs.size());
    for (Eigen::Index i = 0; i < xyz.rows(); ++i) {
      const std::array<double, 3> key = {xyz(i, 0), xyz(i, 1), xyz(i, 2)};
      const auto [it, fresh] = welded.emplace(key, static_cast<int>(positions.size()));
      if (fresh) positions.emplace_back(xyz(i, 0), xyz(i, 1), xyz(i, 2));
      vertex[static_cast<std::size_t>(i)] = it->second;
      uvs.emplace_back(st(i, 0), 1.0 - st(i, 1));
    }
    std::vector<long> index;
    if (p.indices >= 0) {
      index = integers(p.indices);
    } else {
      for (Eigen::Index i = 0; i < xyz.rows(); ++i) index.push_back(i);
    }
    for (std::size_t i = 0; i + 2 < index.size(); i += 3) {
      std::array<int, 3> face{}, uv_face{};
      for (int c = 0; c < 3; ++c) {
        const long k = index[i + c];
        if (k < 0 || k >= xyz.rows()) throw InvalidInput(path + ": an index is out of range");
        face[c] = vertex[static_cast<std::size_t>(k)];
        uv_face[c] = uv_base + static_cast<int>(k);
      }
      faces.push_back(face);
      uv_faces.push_back(uv_face);
    }
  }
  if (faces.empty()) throw InvalidInput(path + ": the glTF file's first mesh has no triangles");
  result.mesh.positions.resize(static_cast<Eigen::Index>(positions.size()), 3);
  for (std::size_t v = 0; v < positions.size(); ++v) {
    result.mesh.positions.row(static_cast<Eigen::Index>(v)) = positions[v].transpose();
  }
  result.mesh.triangles.resize(static_cast<Eigen::Index>(faces.size()), 3);
  result.uv_triangles.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (std::size_t f = 0; f < faces.size(); ++f) {
    for (int c = 0; c < 3; ++c) {
      result.mesh.triangles(static_cast<Eigen::Index>(f), c) = faces[f][c];
      result.uv_triangles(static_cast<Eigen::Index>(f), c) = uv_faces[f][c];
    }
  }
  result.uv.resize(static_cast<Eigen::Index>(uvs.size()), 2);
  for (std::size_t t = 0; t < uvs.size(); ++t) {
    result.uv.row(static_cast<Eigen::Index>(t)) = uvs[t].transpose();
  }
  return result;
#endif
}

TexturedMesh read_textured_file(const std::string& path) {
  std::string extension = fs::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return extension == ".glb" ? read_glb(path) : read_textured_obj(path);
}

bool glb_supported() {
#ifdef RICCI_HAVE_GLTF
  return true;
#else
  return false;
#endif
}

namespace {

#ifdef RICCI_HAVE_GLTF
/// The vertex data of a glb file, as stored: one glTF vertex per (position, uv) pair, so that a
/// seam vertex appears once per side.
struct GlbVertices {
  std::size_t count = 0;
  std::vector<float> positions, normals, texcoords;  ///< 3, 3 and 2 per vertex
  std::vector<double> low, high;                     ///< the stored positions' box
  std::vector<std::uint32_t> indices;                ///< 3 per face
};

/// The glTF vertices of a textured mesh, with area-weighted vertex normals when asked (else
/// +z, which the writer leaves out).
GlbVertices glb_vertices(const TexturedMesh& textured, bool with_normals) {
  const Mesh& mesh = textured.mesh;
  const Triangles& uv_triangles = textured.uv_triangles;
  const Eigen::Matrix<double, Eigen::Dynamic, 2>& uv = textured.uv;
  const int n = mesh.num_faces();
  GlbVertices out;
  std::map<std::pair<int, int>, std::uint32_t> vertex_of;
  std::vector<std::pair<int, int> > corners_of;
  out.indices.reserve(static_cast<std::size_t>(3) * n);
  for (int f = 0; f < n; ++f) {
    for (int c = 0; c < 3; ++c) {
      const std::pair<int, int> key{mesh.triangles(f, c), uv_triangles(f, c)};
      const auto [it, fresh] =
          vertex_of.emplace(key, static_cast<std::uint32_t>(corners_of.size()));
      if (fresh) corners_of.push_back(key);
      out.indices.push_back(it->second);
    }
  }
  Eigen::MatrixX3d normals = Eigen::MatrixX3d::Zero(mesh.num_vertices(), 3);
  if (with_normals) {
    for (int f = 0; f < n; ++f) {
      const Eigen::Vector3d a = mesh.positions.row(mesh.triangles(f, 0));
      const Eigen::Vector3d b = mesh.positions.row(mesh.triangles(f, 1));
      const Eigen::Vector3d c = mesh.positions.row(mesh.triangles(f, 2));
      const Eigen::Vector3d area_normal = (b - a).cross(c - a);  // twice the area, outward
      for (int k = 0; k < 3; ++k) normals.row(mesh.triangles(f, k)) += area_normal.transpose();
    }
  }
  const std::size_t count = corners_of.size();
  out.count = count;
  out.positions.resize(3 * count);
  out.normals.resize(3 * count);
  out.texcoords.resize(2 * count);
  out.low.assign(3, std::numeric_limits<double>::infinity());
  out.high.assign(3, -std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < count; ++i) {
    const auto [v, t] = corners_of[i];
    Eigen::Vector3d normal = normals.row(v);
    normal = normal.norm() > 0 ? normal.normalized() : Eigen::Vector3d(0, 0, 1);
    for (int k = 0; k < 3; ++k) {
      out.positions[3 * i + k] = static_cast<float>(mesh.positions(v, k));
      out.normals[3 * i + k] = static_cast<float>(normal[k]);
      out.low[k] = std::min(out.low[k], static_cast<double>(out.positions[3 * i + k]));
      out.high[k] = std::max(out.high[k], static_cast<double>(out.positions[3 * i + k]));
    }
    out.texcoords[2 * i] = static_cast<float>(uv(t, 0));
    out.texcoords[2 * i + 1] = static_cast<float>(1.0 - uv(t, 1));  // glTF's t runs downwards
  }
  return out;
}

/// Appends `bytes` at the next 4-byte boundary of the model's one buffer as a new buffer view;
/// its index.
int add_view(tinygltf::Model& model, tinygltf::Buffer& buffer, const void* data, std::size_t bytes,
             int target) {
  while (buffer.data.size() % 4 != 0) buffer.data.push_back(0);  // 4-byte alignment
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = buffer.data.size();
  view.byteLength = bytes;
  view.target = target;
  const auto* first = static_cast<const unsigned char*>(data);
  buffer.data.insert(buffer.data.end(), first, first + bytes);
  model.bufferViews.push_back(view);
  return static_cast<int>(model.bufferViews.size() - 1);
}

/// A new accessor of `elements` elements on buffer view `view`; its index.
int add_accessor(tinygltf::Model& model, int view, int component, int type, std::size_t elements) {
  tinygltf::Accessor accessor;
  accessor.bufferView = view;
  accessor.componentType = component;
  accessor.type = type;
  accessor.count = elements;
  model.accessors.push_back(accessor);
  return static_cast<int>(model.accessors.size() - 1);
}

/// The accessors of the vertex data, and the buffer view of the texture image.
struct GlbData {
  int positions = -1, normals = -1, texcoords = -1, indices = -1;
  int image_view = -1;
};

/// The model's one buffer: the vertex data, then the texture image's bytes.
GlbData add_buffer(tinygltf::Model& model, const GlbVertices& v, const std::string& texture) {
  tinygltf::Buffer buffer;
  GlbData data;
  const std::size_t count = v.count;
  data.positions =
      add_accessor(model,
                   add_view(model, buffer, v.positions.data(), v.positions.size() * sizeof(float),
                            TINYGLTF_TARGET_ARRAY_BUFFER),
                   TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, count);
  model.accessors[data.positions].minValues = v.low;
  model.accessors[data.positions].maxValues = v.high;
  data.normals =
      add_accessor(model,
                   add_view(model, buffer, v.normals.data(), v.normals.size() * sizeof(float),
                            TINYGLTF_TARGET_ARRAY_BUFFER),
                   TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, count);
  data.texcoords =
      add_accessor(model,
                   add_view(model, buffer, v.texcoords.data(), v.texcoords.size() * sizeof(float),
                            TINYGLTF_TARGET_ARRAY_BUFFER),
                   TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2, count);
  data.indices = add_accessor(
      model,
      add_view(model, buffer, v.indices.data(), v.indices.size() * sizeof(std::uint32_t),
               TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER),
      TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR, v.indices.size());
  data.image_view = add_view(model, buffer, texture.data(), texture.size(), 0);
  model.bufferViews[data.image_view].target = 0;  // images are not vertex data
  buffer.data.resize((buffer.data.size() + 3) / 4 * 4, 0);
  model.buffers.push_back(std::move(buffer));
  return data;
}

/// The texture (repeated, filtered) and the one material that shows it.
void add_material(tinygltf::Model& model, int image_view, const std::string& mime) {
  tinygltf::Image image;
  image.name = "texture";
  image.bufferView = image_view;
  image.mimeType = mime;
  model.images.push_back(image);
  tinygltf::Sampler sampler;
  sampler.magFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
  sampler.minFilter = TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR;
  sampler.wrapS = TINYGLTF_TEXTURE_WRAP_REPEAT;
  sampler.wrapT = TINYGLTF_TEXTURE_WRAP_REPEAT;
  model.samplers.push_back(sampler);
  tinygltf::Texture gl_texture;
  gl_texture.sampler = 0;
  gl_texture.source = 0;
  model.textures.push_back(gl_texture);
  tinygltf::Material material;
  material.name = ObjMaterial{}.name;
  material.pbrMetallicRoughness.baseColorTexture.index = 0;
  material.pbrMetallicRoughness.metallicFactor = 0.0;
  material.pbrMetallicRoughness.roughnessFactor = 0.9;
  material.doubleSided = true;
  model.materials.push_back(material);
}

/// One mesh of one primitive (named `name`), in one node of the default scene.
void add_scene(tinygltf::Model& model, const GlbData& data, bool with_normals,
               const std::string& name) {
  tinygltf::Primitive primitive;
  primitive.attributes["POSITION"] = data.positions;
  if (with_normals) primitive.attributes["NORMAL"] = data.normals;
  primitive.attributes["TEXCOORD_0"] = data.texcoords;
  primitive.indices = data.indices;
  primitive.material = 0;
  primitive.mode = TINYGLTF_MODE_TRIANGLES;
  tinygltf::Mesh gl_mesh;
  gl_mesh.name = name;
  gl_mesh.primitives.push_back(primitive);
  model.meshes.push_back(gl_mesh);
  tinygltf::Node node;
  node.mesh = 0;
  node.name = gl_mesh.name;
  model.nodes.push_back(node);
  tinygltf::Scene scene;
  scene.nodes.push_back(0);
  model.scenes.push_back(scene);
  model.defaultScene = 0;
}
#endif

/// glb_writer's writer; write_mesh has checked the indices and coordinates.
void write_glb(const std::string& path, const TexturedMesh& textured, const GlbOptions& options) {
  const std::string texture = options.texture_path.empty() ? encode_png(checkerboard_texture())
                                                           : read_bytes(options.texture_path);
  const std::string mime = image_mime_type(
      texture, options.texture_path.empty() ? std::string("checkerboard") : options.texture_path);
#ifndef RICCI_HAVE_GLTF
  (void)mime;
  (void)textured;
  throw IoError("write_glb: " + path +
                ": this ricci was built without tinygltf (install libtinygltf-dev and rebuild)");
#else
  const GlbVertices vertices = glb_vertices(textured, options.normals);
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "ricci";
  const GlbData data = add_buffer(model, vertices, texture);
  add_material(model, data.image_view, mime);
  add_scene(model, data, options.normals, fs::path(path).stem().string());
  write_file_atomically(path, [&](std::ostream& out) {
    tinygltf::TinyGLTF writer;
    if (!writer.WriteGltfSceneToStream(&model, out, false, true)) {
      throw std::runtime_error("tinygltf could not write the glTF binary");
    }
  });
#endif
}

}  // namespace

MeshWriter glb_writer(const GlbOptions& options) {
  return [options](const std::string& path, const TexturedMesh& mesh) {
    write_glb(path, mesh, options);
  };
}

}  // namespace ricci

#include "control/render/renderer.h"

#include <algorithm>
#include <cstring>
#include <map>
#include <opencv2/imgproc.hpp>
#include <string>

#include "common/geometry/gl_camera.h"
#include "control/render/gl.h"

namespace igms::control::render {
namespace {

// A triangle over the whole viewport from gl_VertexID alone (no vertex buffer); `ndc` is the
// fragment's normalised device position.
constexpr const char* kFullViewportVs = R"(#version 330 core
out vec2 ndc;
void main() {
  vec2 p = vec2(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0);
  ndc = p;
  gl_Position = vec4(p, 0.0, 1.0);
})";

// The video: each viewport pixel is an ideal pixel of the eye's camera; with a lens it is
// read from where the lens put it (OpenCV's model, k1 k2 p1 p2 k3 k4 k5 k6), so the video
// is undistorted and the ideal camera's graphics register on it.
constexpr const char* kVideoFs = R"(#version 330 core
in vec2 ndc;
uniform sampler2D video;
uniform vec2 image_size;
uniform vec2 offset;
uniform int has_video;
uniform int has_lens;
uniform mat3 K;
uniform mat3 K_inv;
uniform float dist[8];
out vec4 color;
void main() {
  vec2 uv = vec2((ndc.x + 1.0) * 0.5 * image_size.x - 0.5,
                 (1.0 - ndc.y) * 0.5 * image_size.y - 0.5);
  uv -= offset;
  if (has_lens == 1) {
    vec3 x = K_inv * vec3(uv, 1.0);
    vec2 n = x.xy / x.z;
    float r2 = dot(n, n);
    float radial = (1.0 + r2 * (dist[0] + r2 * (dist[1] + r2 * dist[4]))) /
                   (1.0 + r2 * (dist[5] + r2 * (dist[6] + r2 * dist[7])));
    vec2 d = n * radial + vec2(2.0 * dist[2] * n.x * n.y + dist[3] * (r2 + 2.0 * n.x * n.x),
                               dist[2] * (r2 + 2.0 * n.y * n.y) + 2.0 * dist[3] * n.x * n.y);
    vec3 p = K * vec3(d, 1.0);
    uv = p.xy / p.z;
  }
  vec2 tc = (uv + 0.5) / image_size;
  if (has_video == 0 || any(lessThan(tc, vec2(0.0))) || any(greaterThan(tc, vec2(1.0)))) {
    color = vec4(0.0, 0.0, 0.0, 1.0);
  } else {
    color = vec4(texture(video, tc).rgb, 1.0);
  }
})";

constexpr const char* kModelVs = R"(#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
layout(location = 2) in vec3 color_in;
uniform mat4 mvp;
uniform vec3 eye;
uniform int shaded;
out vec3 color_v;
void main() {
  gl_Position = mvp * vec4(position, 1.0);
  if (shaded == 1) {
    float l = abs(dot(normalize(normal), normalize(eye - position)));
    color_v = color_in * (0.35 + 0.65 * l);
  } else {
    color_v = color_in;
  }
})";

// The thesis's keyer: graphics no brighter than key_level are transparent.
constexpr const char* kModelFs = R"(#version 330 core
in vec3 color_v;
uniform float key_level;
uniform float alpha;
out vec4 color;
void main() {
  if (max(color_v.r, max(color_v.g, color_v.b)) * 255.0 <= key_level) discard;
  color = vec4(color_v, alpha);
})";

// The same without the keyer, for when it keys out nothing that is drawn (key level 0: only
// black, and black models are left out): a shader that never discards lets the rasteriser
// test depth before shading, which software GL needs with many models.
constexpr const char* kModelUnkeyedFs = R"(#version 330 core
in vec3 color_v;
uniform float alpha;
out vec4 color;
void main() {
  color = vec4(color_v, alpha);
})";

// A box's texture patch, projected from the camera that took it.
constexpr const char* kTexturedVs = R"(#version 330 core
layout(location = 0) in vec3 position;
uniform mat4 mvp;
out vec3 world;
void main() {
  gl_Position = mvp * vec4(position, 1.0);
  world = position;
})";

constexpr const char* kTexturedFs = R"(#version 330 core
in vec3 world;
uniform sampler2D patch;
uniform mat4x3 texture_P;
uniform vec4 rect;  // u0, v0, width, height of the patch in its image
uniform float key_level;
uniform float alpha;
out vec4 color;
void main() {
  vec3 p = texture_P * vec4(world, 1.0);
  vec2 tc = (p.xy / p.z - rect.xy + 0.5) / rect.zw;
  if (p.z <= 0.0 || any(lessThan(tc, vec2(0.0))) || any(greaterThan(tc, vec2(1.0)))) discard;
  vec3 c = texture(patch, tc).rgb;
  if (max(c.r, max(c.g, c.b)) * 255.0 <= key_level) discard;
  color = vec4(c, alpha);
})";

constexpr const char* kHudFs = R"(#version 330 core
in vec2 ndc;
uniform sampler2D hud;
out vec4 color;
void main() {
  color = texture(hud, vec2((ndc.x + 1.0) * 0.5, (1.0 - ndc.y) * 0.5));
})";

Result<GLuint> Compile(GLenum type, const char* source, const char* name) {
  const GLuint shader = glCreateShader(type);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[2048] = {};
    glGetShaderInfoLog(shader, sizeof(log), nullptr, log);
    glDeleteShader(shader);
    return ErrorMessage{std::string("the ") + name + " shader: " + log};
  }
  return shader;
}

Result<GLuint> Link(const char* vs, const char* fs, const char* name) {
  auto v = Compile(GL_VERTEX_SHADER, vs, name);
  if (!v.ok()) return ErrorMessage{v.error()};
  auto f = Compile(GL_FRAGMENT_SHADER, fs, name);
  if (!f.ok()) return ErrorMessage{f.error()};
  const GLuint program = glCreateProgram();
  glAttachShader(program, *v);
  glAttachShader(program, *f);
  glLinkProgram(program);
  glDeleteShader(*v);
  glDeleteShader(*f);
  GLint ok = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[2048] = {};
    glGetProgramInfoLog(program, sizeof(log), nullptr, log);
    glDeleteProgram(program);
    return ErrorMessage{std::string("the ") + name + " program: " + log};
  }
  return program;
}

// How a face turned towards the camera winds on screen: a small triangle in front of it,
// counter-clockwise about the normal that faces the camera, projected by `mvp` (the
// viewport keeps the orientation of normalised device coordinates).
GLenum OutwardWinding(const Eigen::Matrix4f& mvp, const geometry::ProjectiveCamera& camera) {
  const Eigen::Vector3d d = camera.ViewDirection();
  const Eigen::Vector3d a = d.unitOrthogonal(), b = a.cross(d);  // a x b = -d: to the eye
  const Eigen::Vector3d p = camera.Center() + 10.0 * d;
  Eigen::Vector2f s[3];
  int k = 0;
  for (const Eigen::Vector3d& q : {p, Eigen::Vector3d(p + a), Eigen::Vector3d(p + b)}) {
    const Eigen::Vector4f c = mvp * q.cast<float>().homogeneous();
    s[k++] = c.head<2>() / c.w();
  }
  const Eigen::Vector2f e1 = s[1] - s[0], e2 = s[2] - s[0];
  return e1.x() * e2.y() - e1.y() * e2.x() > 0 ? GL_CCW : GL_CW;
}

struct Vertex {
  float position[3];
  float normal[3];
  float color[3];
};

void Push(std::vector<Vertex>* out, const Eigen::Vector3f& p, const Eigen::Vector3f& n,
          const Eigen::Vector3f& c) {
  out->push_back({{p.x(), p.y(), p.z()}, {n.x(), n.y(), n.z()}, {c.x(), c.y(), c.z()}});
}

// Uploads an 8-bit grey or BGR image into `texture` (grey is swizzled to all three channels).
void Upload(GLuint texture, const cv::Mat& image) {
  cv::Mat m = image.isContinuous() ? image : image.clone();
  glBindTexture(GL_TEXTURE_2D, texture);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  if (m.channels() == 1) {
    glTexImage2D(GL_TEXTURE_2D, 0, GL_R8, m.cols, m.rows, 0, GL_RED, GL_UNSIGNED_BYTE, m.data);
    const GLint swizzle[] = {GL_RED, GL_RED, GL_RED, GL_ONE};
    glTexParameteriv(GL_TEXTURE_2D, GL_TEXTURE_SWIZZLE_RGBA, swizzle);
  } else if (m.channels() == 3) {
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB8, m.cols, m.rows, 0, GL_BGR, GL_UNSIGNED_BYTE, m.data);
    const GLint swizzle[] = {GL_RED, GL_GREEN, GL_BLUE, GL_ONE};
    glTexParameteriv(GL_TEXTURE_2D, GL_TEXTURE_SWIZZLE_RGBA, swizzle);
  } else {
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, m.cols, m.rows, 0, GL_BGRA, GL_UNSIGNED_BYTE, m.data);
  }
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

cv::Scalar HudColour(HudLevel level) {  // BGRA
  switch (level) {
    case HudLevel::kWarning:
      return {0, 210, 255, 255};
    case HudLevel::kError:
      return {60, 60, 255, 255};
    case HudLevel::kInfo:
      break;
  }
  return {255, 255, 255, 255};
}

}  // namespace

cv::Mat RenderHudImage(const DrawList& list, int width, int height) {
  cv::Mat hud(height, width, CV_8UC4, cv::Scalar(0, 0, 0, 0));
  const double scale = std::clamp(height / 1100.0, 0.35, 1.0);
  const int font = cv::FONT_HERSHEY_SIMPLEX;
  const int line = static_cast<int>(std::lround(34 * scale)) + 2;
  auto text = [&](const std::string& s, cv::Point at, const cv::Scalar& colour) {
    int baseline = 0;
    const cv::Size size = cv::getTextSize(s, font, scale, 1, &baseline);
    // A dark band behind each line, so text reads over bright video; its alpha keeps the
    // video visible through it.
    cv::rectangle(hud, cv::Point(at.x - 3, at.y - size.height - 3),
                  cv::Point(at.x + size.width + 3, at.y + baseline + 1), cv::Scalar(0, 0, 0, 150),
                  cv::FILLED);
    cv::putText(hud, s, at, font, scale, colour, 1, cv::LINE_AA);
  };
  int y = line;
  for (const HudLine& l : list.hud) {
    text(l.text, {8, y}, HudColour(l.level));
    y += line;
  }
  if (!list.banner.empty()) {
    int baseline = 0;
    const double big = scale * 1.3;
    const cv::Size size = cv::getTextSize(list.banner, font, big, 2, &baseline);
    const cv::Point at((width - size.width) / 2, height / 2);
    cv::rectangle(hud, cv::Point(0, at.y - size.height - 10), cv::Point(width, at.y + 14),
                  cv::Scalar(0, 0, 160, 200), cv::FILLED);
    cv::putText(hud, list.banner, at, font, big, cv::Scalar(255, 255, 255, 255), 2, cv::LINE_AA);
  }
  y = height - 8 - line * static_cast<int>(!list.help.empty() ? list.help.size() - 1 : 0);
  for (const std::string& h : list.help) {
    text(h, {8, y}, cv::Scalar(200, 255, 200, 255));
    y += line;
  }
  return hud;
}

struct Renderer::Impl {
  GLuint video_program = 0, model_program = 0, hud_program = 0, textured_program = 0;
  GLuint unkeyed_program = 0;
  // Box texture patches by the address of their pixels, kept while they are drawn.
  std::map<const void*, GLuint> patches;
  GLuint empty_vao = 0, model_vao = 0, model_vbo = 0;
  GLuint video_texture[2] = {0, 0};
  const void* video_data[2] = {nullptr, nullptr};
  uint64_t video_id[2] = {0, 0};
  GLuint hud_texture = 0;
  std::string hud_key;
  std::vector<Vertex> triangles, lines;
  std::vector<size_t> order;
  std::vector<double> distance;
  Mesh mesh;

  ~Impl() {
    glDeleteProgram(video_program);
    glDeleteProgram(model_program);
    glDeleteProgram(unkeyed_program);
    glDeleteProgram(hud_program);
    glDeleteProgram(textured_program);
    for (auto& [data, texture] : patches) glDeleteTextures(1, &texture);
    glDeleteVertexArrays(1, &empty_vao);
    glDeleteVertexArrays(1, &model_vao);
    glDeleteBuffers(1, &model_vbo);
    glDeleteTextures(2, video_texture);
    glDeleteTextures(1, &hud_texture);
  }

  GLint U(GLuint program, const char* name) { return glGetUniformLocation(program, name); }

  void DrawVideo(const EyeView& eye, int index, const Eigen::Vector2i& offset) {
    glUseProgram(video_program);
    const bool has_video = !eye.video.empty();
    if (has_video && (eye.video_id == 0 || eye.video_id != video_id[index] ||
                      eye.video.data != video_data[index])) {
      Upload(video_texture[index], eye.video);
      video_id[index] = eye.video_id;
      video_data[index] = eye.video.data;
    }
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, video_texture[index]);
    glUniform1i(U(video_program, "video"), 0);
    glUniform2f(U(video_program, "image_size"), static_cast<float>(eye.size.width),
                static_cast<float>(eye.size.height));
    glUniform2f(U(video_program, "offset"), static_cast<float>(offset.x()),
                static_cast<float>(offset.y()));
    glUniform1i(U(video_program, "has_video"), has_video ? 1 : 0);
    const bool lens = eye.lens && !eye.lens->dist.empty();
    glUniform1i(U(video_program, "has_lens"), lens ? 1 : 0);
    if (lens) {
      const Eigen::Matrix3f K = eye.lens->K.cast<float>();
      const Eigen::Matrix3f K_inv = eye.lens->K.inverse().cast<float>();
      glUniformMatrix3fv(U(video_program, "K"), 1, GL_FALSE, K.data());
      glUniformMatrix3fv(U(video_program, "K_inv"), 1, GL_FALSE, K_inv.data());
      float d[8] = {};
      for (size_t i = 0; i < std::min<size_t>(8, eye.lens->dist.size()); ++i) {
        d[i] = static_cast<float>(eye.lens->dist[i]);
      }
      glUniform1fv(U(video_program, "dist"), 8, d);
    }
    glBindVertexArray(empty_vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
  }

  void DrawGraphics(const DrawList& list, const EyeView& eye, int segments) {
    auto gl = geometry::MakeGlCamera(eye.P, eye.size, list.near, list.far);
    if (!gl.ok()) return;  // no camera (a zero P before the calibration): video alone
    const Eigen::Matrix4f mvp = (gl->projection * gl->view).cast<float>();
    const geometry::ProjectiveCamera camera(eye.P, eye.size);
    const Eigen::Vector3d center = camera.Center();

    triangles.clear();
    lines.clear();
    // Solids nearest first, so the depth test spares the shading of what they hide (not when
    // blending, whose result depends on the order).
    const bool opaque = list.graphics_alpha >= 1.0f;
    order.resize(list.models.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    if (opaque && !list.wireframe) {
      distance.resize(list.models.size());
      for (size_t i = 0; i < order.size(); ++i) {
        distance[i] = (list.models[i].center - center).squaredNorm();
      }
      std::stable_sort(order.begin(), order.end(),
                       [&](size_t a, size_t b) { return distance[a] < distance[b]; });
    }
    // Key level 0 keys out black alone: leave black solids out and shade the rest unkeyed.
    const bool unkeyed = list.key_level <= 0;
    for (const size_t index : order) {
      const DrawModel& model = list.models[index];
      mesh.triangles.clear();
      mesh.normals.clear();
      mesh.lines.clear();
      if (!list.wireframe && unkeyed &&
          model.color.maxCoeff() * 255.0f <= static_cast<float>(list.key_level)) {
        continue;
      }
      AppendModel(model, center, segments, &mesh);
      if (!list.wireframe) {
        for (size_t i = 0; i < mesh.triangles.size(); ++i) {
          Push(&triangles, mesh.triangles[i], mesh.normals[i], model.color);
        }
      } else {
        for (const auto& p : mesh.lines) Push(&lines, p, Eigen::Vector3f::Zero(), model.color);
      }
    }
    const size_t model_lines = lines.size();
    const Eigen::Vector3f zero = Eigen::Vector3f::Zero();
    auto cross = [&](const Eigen::Vector3d& at, double size, const Eigen::Vector3f& colour) {
      for (int axis = 0; axis < 3; ++axis) {
        Eigen::Vector3d d = Eigen::Vector3d::Zero();
        d[axis] = size;
        Push(&lines, (at - d).cast<float>(), zero, colour);
        Push(&lines, (at + d).cast<float>(), zero, colour);
      }
    };
    for (const auto& mark : list.marks) cross(mark, 0.5 * list.pointer_size, {1.0f, 0.2f, 1.0f});
    if (list.pointer) cross(*list.pointer, list.pointer_size, {1.0f, 1.0f, 0.1f});

    const Eigen::Vector3f eye_f = center.cast<float>();
    auto use = [&](GLuint program, bool shaded) {
      glUseProgram(program);
      glUniformMatrix4fv(U(program, "mvp"), 1, GL_FALSE, mvp.data());
      glUniform3fv(U(program, "eye"), 1, eye_f.data());
      glUniform1f(U(program, "key_level"), static_cast<float>(list.key_level));
      glUniform1f(U(program, "alpha"), list.graphics_alpha);
      glUniform1i(U(program, "shaded"), shaded ? 1 : 0);
    };
    if (list.graphics_alpha < 1.0f) {
      glEnable(GL_BLEND);
      glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    }
    glBindVertexArray(model_vao);
    glBindBuffer(GL_ARRAY_BUFFER, model_vbo);
    // (Black solids left out may still carry texture patches.)
    if (!list.wireframe && !list.models.empty()) {
      use(unkeyed ? unkeyed_program : model_program, list.lit);
      glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(triangles.size() * sizeof(Vertex)),
                   triangles.data(), GL_STREAM_DRAW);
      glEnable(GL_DEPTH_TEST);
      glDepthFunc(GL_LESS);
      // The solids are closed and convex: their back faces are hidden by their front ones
      // (when opaque), so they are culled instead of rasterised.
      if (opaque) {
        glEnable(GL_CULL_FACE);
        glCullFace(GL_BACK);
        glFrontFace(OutwardWinding(mvp, camera));
      }
      glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(triangles.size()));
      glDisable(GL_CULL_FACE);
      DrawPatches(list, mvp);
      glDisable(GL_DEPTH_TEST);
    }
    if (!lines.empty()) {
      use(model_program, false);
      glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(lines.size() * sizeof(Vertex)),
                   lines.data(), GL_STREAM_DRAW);
      // A wireframe shows every edge, hidden ones too (the thesis's outline models); the
      // pointer and marks are never hidden by a model.
      glDrawArrays(GL_LINES, 0, static_cast<GLsizei>(model_lines));
      glDrawArrays(GL_LINES, static_cast<GLint>(model_lines),
                   static_cast<GLsizei>(lines.size() - model_lines));
    }
    glDisable(GL_BLEND);
  }

  // Over the flat face, at the same depth (GL_LEQUAL), the texture patch of each box.
  void DrawPatches(const DrawList& list, const Eigen::Matrix4f& mvp) {
    std::map<const void*, GLuint> used;
    std::vector<Eigen::Vector3f> face;
    for (const DrawModel& model : list.models) {
      face.clear();
      if (!TexturedFace(model, &face)) continue;
      const void* key = model.texture.data;
      GLuint texture = 0;
      if (auto u = used.find(key); u != used.end()) {
        texture = u->second;
      } else if (auto it = patches.find(key); it != patches.end()) {
        texture = it->second;
        patches.erase(it);
      } else {
        glGenTextures(1, &texture);
        Upload(texture, model.texture);
      }
      used[key] = texture;
      std::vector<Vertex> vertices;
      for (const auto& p : face) Push(&vertices, p, Eigen::Vector3f::Zero(), model.color);
      glUseProgram(textured_program);
      glUniformMatrix4fv(U(textured_program, "mvp"), 1, GL_FALSE, mvp.data());
      const Eigen::Matrix<float, 3, 4> P = model.texture_P.cast<float>();
      glUniformMatrix4x3fv(U(textured_program, "texture_P"), 1, GL_FALSE, P.data());
      glUniform4f(U(textured_program, "rect"), static_cast<float>(model.texture_rect.x),
                  static_cast<float>(model.texture_rect.y),
                  static_cast<float>(model.texture_rect.width),
                  static_cast<float>(model.texture_rect.height));
      glUniform1f(U(textured_program, "key_level"), static_cast<float>(list.key_level));
      glUniform1f(U(textured_program, "alpha"), list.graphics_alpha);
      glActiveTexture(GL_TEXTURE0);
      glBindTexture(GL_TEXTURE_2D, texture);
      glUniform1i(U(textured_program, "patch"), 0);
      glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vertices.size() * sizeof(Vertex)),
                   vertices.data(), GL_STREAM_DRAW);
      glDepthFunc(GL_LEQUAL);
      glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(vertices.size()));
      glDepthFunc(GL_LESS);
    }
    for (auto& [data, texture] : patches) glDeleteTextures(1, &texture);  // no longer drawn
    patches = std::move(used);
    glUseProgram(model_program);
  }

  void DrawHud(const DrawList& list, const Viewport& vp) {
    if (list.hud.empty() && list.banner.empty() && list.help.empty()) return;
    std::string key =
        std::to_string(vp.width) + "x" + std::to_string(vp.height) + "|" + list.banner + "|";
    for (const auto& l : list.hud) key += std::to_string(static_cast<int>(l.level)) + l.text + "\n";
    for (const auto& h : list.help) key += h + "\n";
    if (key != hud_key) {
      Upload(hud_texture, RenderHudImage(list, vp.width, vp.height));
      hud_key = key;
    }
    glUseProgram(hud_program);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, hud_texture);
    glUniform1i(U(hud_program, "hud"), 0);
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glBindVertexArray(empty_vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glDisable(GL_BLEND);
  }
};

Result<std::unique_ptr<Renderer>> Renderer::Make() {
  auto impl = std::make_unique<Impl>();
  auto video = Link(kFullViewportVs, kVideoFs, "video");
  if (!video.ok()) return ErrorMessage{video.error()};
  impl->video_program = *video;
  auto model = Link(kModelVs, kModelFs, "model");
  if (!model.ok()) return ErrorMessage{model.error()};
  impl->model_program = *model;
  auto unkeyed = Link(kModelVs, kModelUnkeyedFs, "unkeyed model");
  if (!unkeyed.ok()) return ErrorMessage{unkeyed.error()};
  impl->unkeyed_program = *unkeyed;
  auto textured = Link(kTexturedVs, kTexturedFs, "texture patch");
  if (!textured.ok()) return ErrorMessage{textured.error()};
  impl->textured_program = *textured;
  auto hud = Link(kFullViewportVs, kHudFs, "hud");
  if (!hud.ok()) return ErrorMessage{hud.error()};
  impl->hud_program = *hud;
  glGenVertexArrays(1, &impl->empty_vao);
  glGenVertexArrays(1, &impl->model_vao);
  glGenBuffers(1, &impl->model_vbo);
  glBindVertexArray(impl->model_vao);
  glBindBuffer(GL_ARRAY_BUFFER, impl->model_vbo);
  for (GLuint i = 0; i < 3; ++i) {
    glEnableVertexAttribArray(i);
    const std::size_t offset = std::size_t{i} * 3 * sizeof(float);  // position, normal, color
    // OpenGL takes the attribute's offset in the bound buffer as a pointer.
    const void* pointer =
        reinterpret_cast<const void*>(offset);  // NOLINT(performance-no-int-to-ptr)
    glVertexAttribPointer(i, 3, GL_FLOAT, GL_FALSE, sizeof(Vertex), pointer);
  }
  glBindVertexArray(0);
  glGenTextures(2, impl->video_texture);
  glGenTextures(1, &impl->hud_texture);
  if (const GLenum e = glGetError(); e != GL_NO_ERROR) {
    return ErrorMessage{"OpenGL error " + std::to_string(e) + " setting up the renderer"};
  }
  return std::unique_ptr<Renderer>(new Renderer(std::move(impl)));
}

Renderer::Renderer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Renderer::~Renderer() = default;

void Renderer::Clear(int width, int height) {
  glDisable(GL_SCISSOR_TEST);
  glViewport(0, 0, width, height);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glClearColor(0, 0, 0, 1);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
}

void Renderer::DrawEye(const DrawList& list, int eye, const Viewport& vp,
                       std::array<bool, 3> mask) {
  const EyeView& view = list.eyes[eye];
  glViewport(vp.x, vp.y, vp.width, vp.height);
  glScissor(vp.x, vp.y, vp.width, vp.height);
  glEnable(GL_SCISSOR_TEST);
  glColorMask(mask[0], mask[1], mask[2], GL_TRUE);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  impl_->DrawVideo(view, eye, list.video_offset);
  glClear(GL_DEPTH_BUFFER_BIT);
  impl_->DrawGraphics(list, view, std::max(8, cylinder_segments));
  impl_->DrawHud(list, vp);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glDisable(GL_SCISSOR_TEST);
  glUseProgram(0);
  glBindVertexArray(0);
}

}  // namespace igms::control::render

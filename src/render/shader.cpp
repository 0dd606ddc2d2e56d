#include "render/shader.hpp"

#include <glad/gl.h>

#include <algorithm>
#include <fstream>
#include <sstream>
#include <utility>

#include "render/render_error.hpp"

namespace weft {

namespace {

std::string read_text_file(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw RenderError(path + ": cannot read shader file");
  std::ostringstream text;
  text << file.rdbuf();
  return text.str();
}

std::string shader_log(GLuint shader) {
  GLint length = 0;
  glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
  std::string log(static_cast<size_t>(std::max(length, 1)), '\0');
  glGetShaderInfoLog(shader, length, nullptr, log.data());
  return log.c_str();
}

std::string program_log(GLuint program) {
  GLint length = 0;
  glGetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
  std::string log(static_cast<size_t>(std::max(length, 1)), '\0');
  glGetProgramInfoLog(program, length, nullptr, log.data());
  return log.c_str();
}

GLuint compile_shader_file(GLenum kind, const std::string& path) {
  const std::string source = read_text_file(path);
  const char* text = source.c_str();
  const GLuint shader = glCreateShader(kind);
  glShaderSource(shader, 1, &text, nullptr);
  glCompileShader(shader);
  GLint compiled = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &compiled);
  if (compiled != GL_TRUE) {
    const std::string log = shader_log(shader);
    glDeleteShader(shader);
    throw RenderError(path + ": shader does not compile:\n" + log);
  }
  return shader;
}

}  // namespace

ShaderProgram::ShaderProgram(const std::string& vertex_path, const std::string& fragment_path) {
  const GLuint vertex = compile_shader_file(GL_VERTEX_SHADER, vertex_path);
  GLuint fragment = 0;
  try {
    fragment = compile_shader_file(GL_FRAGMENT_SHADER, fragment_path);
  } catch (...) {
    glDeleteShader(vertex);
    throw;
  }
  program_ = glCreateProgram();
  glAttachShader(program_, vertex);
  glAttachShader(program_, fragment);
  glLinkProgram(program_);
  // The program keeps what it needs; the shader objects go once it is linked.
  glDeleteShader(vertex);
  glDeleteShader(fragment);
  GLint linked = GL_FALSE;
  glGetProgramiv(program_, GL_LINK_STATUS, &linked);
  if (linked != GL_TRUE) {
    const std::string log = program_log(program_);
    glDeleteProgram(program_);
    program_ = 0;
    throw RenderError(vertex_path + " + " + fragment_path + ": shaders do not link:\n" + log);
  }
}

ShaderProgram::~ShaderProgram() {
  if (program_ != 0) glDeleteProgram(program_);
}

ShaderProgram::ShaderProgram(ShaderProgram&& other) noexcept : program_(std::exchange(other.program_, 0)) {}

ShaderProgram& ShaderProgram::operator=(ShaderProgram&& other) noexcept {
  if (this != &other) {
    if (program_ != 0) glDeleteProgram(program_);
    program_ = std::exchange(other.program_, 0);
  }
  return *this;
}

void ShaderProgram::use() const { glUseProgram(program_); }

void ShaderProgram::set(const char* name, float value) const {
  glUniform1f(glGetUniformLocation(program_, name), value);
}

void ShaderProgram::set(const char* name, int value) const {
  glUniform1i(glGetUniformLocation(program_, name), value);
}

void ShaderProgram::set(const char* name, const Eigen::Vector3f& value) const {
  glUniform3fv(glGetUniformLocation(program_, name), 1, value.data());
}

void ShaderProgram::set(const char* name, const Eigen::Matrix4f& value) const {
  // Eigen is column-major like GLSL, so no transpose.
  glUniformMatrix4fv(glGetUniformLocation(program_, name), 1, GL_FALSE, value.data());
}

}  // namespace weft

#pragma once
// A linked GLSL program read from a vertex and a fragment shader file. Needs a current GL context.
#include <string>

#include <Eigen/Core>

namespace weft {

class ShaderProgram {
 public:
  // Reads, compiles and links; throws RenderError naming the file that failed with the driver's log.
  ShaderProgram(const std::string& vertex_path, const std::string& fragment_path);
  ~ShaderProgram();
  ShaderProgram(ShaderProgram&& other) noexcept;
  ShaderProgram& operator=(ShaderProgram&& other) noexcept;
  ShaderProgram(const ShaderProgram&) = delete;
  ShaderProgram& operator=(const ShaderProgram&) = delete;

  void use() const;
  // Uniform setters for the program in use; a name the program does not have is ignored.
  void set(const char* name, float value) const;
  void set(const char* name, int value) const;
  void set(const char* name, const Eigen::Vector3f& value) const;
  void set(const char* name, const Eigen::Matrix4f& value) const;

 private:
  unsigned int program_ = 0;
};

}  // namespace weft

#include "physics/cloth.hpp"

namespace weft {

Cloth make_cloth(ClothModel model) {
  Cloth cloth;
  const Eigen::Index n = model.rest_positions.cols();
  cloth.state.x = model.rest_positions;
  cloth.state.v = Positions::Zero(3, n);
  cloth.state.force = Positions::Zero(3, n);
  cloth.model = std::move(model);
  return cloth;
}

}  // namespace weft

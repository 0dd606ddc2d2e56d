#include "sim/stability.hpp"

#include <algorithm>
#include <cmath>

#include <cstdio>
#include <vector>

#include "physics/air_drag.hpp"
#include "physics/bending.hpp"
#include "physics/membrane_stvk.hpp"
#include "physics/volume_pressure.hpp"

namespace weft {

namespace {

// Force of each term on one vertex at the cloth's current state; picks the non-finite or largest.
void blame_term(const Cloth& cloth, int vertex, const Vec3& gravity, Instability& found) {
  const ClothModel& model = cloth.model;
  const Positions& x = cloth.state.x;
  const Positions& v = cloth.state.v;
  const SpringSet& springs = model.springs;
  struct TermForce {
    std::string name;
    Vec3 force = Vec3::Zero();
  };
  std::vector<TermForce> terms;
  for (int kind = 0; kind < spring_kind_count; ++kind) {
    TermForce term{std::string(to_string(static_cast<SpringKind>(kind))) + " springs"};
    for (int s = springs.kind_begin[kind]; s < springs.kind_begin[kind + 1]; ++s) {
      const int a = springs.vertices(0, s), b = springs.vertices(1, s);
      if (a != vertex && b != vertex) continue;
      const int other = a == vertex ? b : a;
      const Vec3 d = x.col(other) - x.col(vertex);
      const double length = d.norm();
      term.force += springs.stiffness[s] * (length - springs.rest_length[s]) * d / length +
                    springs.damping[s] * (v.col(other) - v.col(vertex)).dot(d) * d / (length * length);
    }
    terms.push_back(term);
  }
  // Whole-cloth terms, evaluated once here (a failure path, so cost does not matter).
  const int n = cloth.num_vertices();
  Positions gradient(3, n);
  if (model.membrane.enabled()) {
    gradient.setZero();
    evaluate_membrane(model.membrane, model.triangles, x, &gradient, nullptr, -1, false);
    terms.push_back({"membrane", -gradient.col(vertex)});
  }
  if (model.bending.enabled()) {
    gradient.setZero();
    evaluate_bending(model.bending, x, &gradient, nullptr, -1, false);
    terms.push_back({"bending", -gradient.col(vertex)});
  }
  if (model.pressure.enabled) {
    gradient.setZero();
    evaluate_pressure(model.pressure, model.triangles, x, &gradient, nullptr, -1, false);
    terms.push_back({"pressure", -gradient.col(vertex)});
  }
  if (model.air_drag.enabled()) {
    Positions force = Positions::Zero(3, n);
    add_air_drag_forces(model.air_drag, model.triangles, x, v, force);
    terms.push_back({"air drag", force.col(vertex)});
  }
  terms.push_back({"gravity", model.mass[vertex] * gravity});
  if (model.mass_damping > 0.0)
    terms.push_back({"mass damping", -model.mass_damping * model.mass[vertex] * v.col(vertex)});

  const TermForce* worst = nullptr;
  for (const TermForce& term : terms) {
    if (!term.force.allFinite()) {
      worst = &term;
      break;
    }
    if (worst == nullptr || term.force.norm() > worst->force.norm()) worst = &term;
  }
  if (worst != nullptr) {
    found.term = worst->name;
    found.term_force = worst->force.allFinite() ? worst->force.norm() : HUGE_VAL;
  }
}

Instability at_vertex(const World& world, int c, int vertex, const std::string& quantity, double value) {
  Instability found;
  found.found = true;
  found.cloth = c;
  found.vertex = vertex;
  found.cloth_name = world.cloths()[c].model.name;
  found.quantity = quantity;
  found.value = value;
  blame_term(world.cloths()[c], vertex, world.settings.gravity, found);
  return found;
}

}  // namespace

std::string Instability::describe() const {
  if (!found) return {};
  char text[512];
  if (quantity == "position" || quantity == "velocity") {
    std::snprintf(text, sizeof text, "cloth \"%s\" vertex %d has a non-finite %s", cloth_name.c_str(), vertex,
                  quantity.c_str());
  } else if (quantity == "speed") {
    std::snprintf(text, sizeof text, "cloth \"%s\" vertex %d moves at %.4g m/s, past the bound (--max-speed)",
                  cloth_name.c_str(), vertex, value);
  } else if (quantity == "membrane_strain") {
    std::snprintf(text, sizeof text,
                  "cloth \"%s\" vertex %d is in membrane triangle %d, stretched %.4g times its rest size "
                  "along its principal direction, past the bound (--max-strain)",
                  cloth_name.c_str(), vertex, element, value + 1.0);
  } else {
    std::snprintf(text, sizeof text,
                  "cloth \"%s\" vertex %d has a spring (%d) stretched %.4g times its rest length, "
                  "past the bound (--max-strain)",
                  cloth_name.c_str(), vertex, element, value + 1.0);
  }
  std::string message = text;
  if (!term.empty()) {
    std::snprintf(text, sizeof text, "; the largest force on it is from the term \"%s\" (|f| = %.4g N)",
                  term.c_str(), term_force);
    message += text;
  }
  return message;
}

Instability check_state(const World& world, const StabilityLimits& limits) {
  const double max_speed_squared = limits.max_speed * limits.max_speed;
  for (size_t c = 0; c < world.cloths().size(); ++c) {
    const ClothState& state = world.cloths()[c].state;
    // The common case first: one vectorised pass over both arrays.
    const bool finite = state.x.allFinite() && state.v.allFinite();
    const double fastest = finite ? state.v.colwise().squaredNorm().maxCoeff() : 0.0;
    if (finite && (limits.max_speed <= 0.0 || fastest <= max_speed_squared)) continue;
    for (int i = 0; i < static_cast<int>(state.x.cols()); ++i) {
      if (!state.x.col(i).allFinite()) return at_vertex(world, c, i, "position", NAN);
      if (!state.v.col(i).allFinite()) return at_vertex(world, c, i, "velocity", NAN);
    }
    for (int i = 0; i < static_cast<int>(state.x.cols()); ++i) {
      if (state.v.col(i).squaredNorm() > max_speed_squared)
        return at_vertex(world, c, i, "speed", state.v.col(i).norm());
    }
  }
  return {};
}

namespace {

// Calls visit(cloth, vertex, quantity, element, strain) for every spring ("strain") and membrane
// triangle ("membrane_strain") of every cloth, with strain = stretch - 1; stops when it returns
// true and returns whether that happened.
template <class Visit>
bool visit_strains(const World& world, const Visit& visit) {
  for (size_t c = 0; c < world.cloths().size(); ++c) {
    const Cloth& cloth = world.cloths()[c];
    const SpringSet& springs = cloth.model.springs;
    for (int s = 0; s < springs.size(); ++s) {
      if (springs.rest_length[s] <= 0.0 || springs.stiffness[s] <= 0.0) continue;  // not a force term
      const int a = springs.vertices(0, s), b = springs.vertices(1, s);
      const double strain =
          (cloth.state.x.col(b) - cloth.state.x.col(a)).norm() / springs.rest_length[s] - 1.0;
      if (visit(static_cast<int>(c), a, "strain", s, strain)) return true;
    }
    // Membrane: the largest principal stretch sqrt(1 + 2 e_max) of each triangle.
    const MembraneTerm& membrane = cloth.model.membrane;
    const Triangles& triangles = cloth.model.triangles;
    const Positions& x = cloth.state.x;
    for (int t = 0; t < static_cast<int>(membrane.rest.size()); ++t) {
      const Eigen::Matrix2d strain_tensor = green_strain(x.col(triangles(0, t)), x.col(triangles(1, t)),
                                                         x.col(triangles(2, t)), membrane.rest[t]);
      const double largest = largest_principal_strain(strain_tensor);
      const double strain = std::sqrt(std::max(0.0, 1.0 + 2.0 * largest)) - 1.0;
      if (visit(static_cast<int>(c), triangles(0, t), "membrane_strain", t, strain)) return true;
    }
  }
  return false;
}

}  // namespace

Instability check_strain(const World& world, const StabilityLimits& limits) {
  if (limits.max_strain <= 0.0) return {};
  Instability found;
  visit_strains(world, [&](int c, int vertex, const char* quantity, int element, double strain) {
    if (!(strain > limits.max_strain)) return false;
    found = at_vertex(world, c, vertex, quantity, strain);
    found.element = element;
    return true;
  });
  return found;
}

double largest_strain(const World& world) {
  double largest = 0.0;
  visit_strains(world, [&](int, int, const char*, int, double strain) {
    largest = std::max(largest, strain);
    return false;
  });
  return largest;
}

}  // namespace weft

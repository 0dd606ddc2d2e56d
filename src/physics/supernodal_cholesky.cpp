#include "physics/supernodal_cholesky.hpp"

#include <algorithm>

#include <Eigen/OrderingMethods>

namespace weft {

void SupernodalCholesky::analyze(const Matrix& matrix) {
  const int n = static_cast<int>(matrix.rows()) / 3;
  num_vertices_ = n;

  // Vertex graph (block pattern) and its AMD ordering.
  std::vector<std::vector<int>> neighbours(n);
  for (int v = 0; v < n; ++v) {
    for (Matrix::InnerIterator it(matrix, 3 * v); it; ++it) {
      const int w = static_cast<int>(it.col()) / 3;
      if (neighbours[v].empty() || neighbours[v].back() != w) neighbours[v].push_back(w);
    }
  }
  {
    std::vector<Eigen::Triplet<double>> entries;
    for (int v = 0; v < n; ++v) {
      for (int w : neighbours[v]) entries.emplace_back(v, w, 1.0);
      entries.emplace_back(v, v, 1.0);
    }
    Eigen::SparseMatrix<double, Eigen::ColMajor, int> graph(n, n);
    graph.setFromTriplets(entries.begin(), entries.end());
    Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> ordering;
    Eigen::AMDOrdering<int>()(graph, ordering);
    old_of_new_.assign(ordering.indices().data(), ordering.indices().data() + n);
  }
  new_of_old_.assign(n, 0);
  for (int k = 0; k < n; ++k) new_of_old_[old_of_new_[k]] = k;

  // Elimination tree of the permuted graph (Liu's algorithm with path compression).
  std::vector<int> parent(n, -1), ancestor(n, -1);
  for (int k = 0; k < n; ++k) {
    for (int w : neighbours[old_of_new_[k]]) {
      for (int r = new_of_old_[w]; r < k;) {
        const int next = ancestor[r];
        ancestor[r] = k;
        if (next == -1) {
          parent[r] = k;
          break;
        }
        if (next == k) break;
        r = next;
      }
    }
  }

  // Row structure of each column of L below the diagonal: the column's own lower neighbours
  // and its children's structures (children come first, since parent > child).
  std::vector<std::vector<int>> structure(n);
  std::vector<int> mark(n, -1);
  std::vector<std::vector<int>> children(n);
  for (int k = 0; k < n; ++k) {
    if (parent[k] != -1) children[parent[k]].push_back(k);
  }
  for (int k = 0; k < n; ++k) {
    std::vector<int>& rows = structure[k];
    mark[k] = k;
    for (int w : neighbours[old_of_new_[k]]) {
      const int r = new_of_old_[w];
      if (r > k && mark[r] != k) {
        mark[r] = k;
        rows.push_back(r);
      }
    }
    for (int c : children[k]) {
      for (int r : structure[c]) {
        if (r != k && mark[r] != k) {
          mark[r] = k;
          rows.push_back(r);
        }
      }
    }
    std::sort(rows.begin(), rows.end());
  }

  // Supernodes: column k joins k - 1's when k is its parent and their structures nest exactly.
  std::vector<int> supernode_of(n, -1);
  supernodes_.clear();
  for (int k = 0; k < n; ++k) {
    const bool joins = k > 0 && parent[k - 1] == k && structure[k - 1].size() == structure[k].size() + 1;
    if (!joins) {
      supernodes_.emplace_back();
      supernodes_.back().first = k;
    }
    ++supernodes_.back().width;
    supernode_of[k] = static_cast<int>(supernodes_.size()) - 1;
  }
  int largest = 0;
  for (Supernode& s : supernodes_) {
    s.rows.clear();
    for (int k = 0; k < s.width; ++k) s.rows.push_back(s.first + k);
    const int last = s.first + s.width - 1;
    s.rows.insert(s.rows.end(), structure[last].begin(), structure[last].end());
    s.parent = parent[last] == -1 ? -1 : supernode_of[parent[last]];
    largest = std::max(largest, 3 * static_cast<int>(s.rows.size()));
  }
  for (std::vector<int>& rows : structure) std::vector<int>().swap(rows);

  // Where each child's update lands in its parent's front, and where each matrix entry lands.
  front_.resize(largest, largest);
  const int stride = largest;
  std::vector<int> local(n, -1);
  for (int i = 0; i < num_supernodes(); ++i) {
    Supernode& s = supernodes_[i];
    for (int r = 0; r < static_cast<int>(s.rows.size()); ++r) local[s.rows[r]] = r;
    for (int c = 0; c < s.width; ++c) {
      const int column_vertex = s.first + c;
      for (int a = 0; a < 3; ++a) {
        const int row = 3 * old_of_new_[column_vertex] + a;
        for (int index = matrix.outerIndexPtr()[row]; index < matrix.outerIndexPtr()[row + 1]; ++index) {
          const int col = matrix.innerIndexPtr()[index];
          const int other = new_of_old_[col / 3];
          const int b = col % 3;
          if (other < column_vertex || (other == column_vertex && b < a)) continue;  // upper triangle
          s.assembly.emplace_back(index, (3 * c + a) * stride + 3 * local[other] + b);
        }
      }
    }
    s.panel.resize(3 * s.rows.size(), 3 * s.width);
    const int below = 3 * (static_cast<int>(s.rows.size()) - s.width);
    s.update.resize(below, below);
  }
  for (int i = 0; i < num_supernodes(); ++i) {
    Supernode& s = supernodes_[i];
    if (s.parent == -1) continue;
    supernodes_[s.parent].children.push_back(i);
    const Supernode& p = supernodes_[s.parent];
    for (int r = 0; r < static_cast<int>(p.rows.size()); ++r) local[p.rows[r]] = r;
    s.in_parent.clear();
    for (int r = s.width; r < static_cast<int>(s.rows.size()); ++r) s.in_parent.push_back(local[s.rows[r]]);
  }
  permuted_.resize(3 * n);
  gathered_.resize(largest);
}

bool SupernodalCholesky::factorize(const Matrix& matrix) {
  const double* values = matrix.valuePtr();
  for (Supernode& s : supernodes_) {
    const int m = 3 * static_cast<int>(s.rows.size());
    const int k = 3 * s.width;
    auto front = front_.topLeftCorner(m, m);
    front.triangularView<Eigen::Lower>().setZero();
    double* data = front_.data();
    for (const auto& [index, position] : s.assembly) data[position] += values[index];
    // Extend-add: each child's update (lower triangle, by 3x3 blocks) into this front.
    for (int c : s.children) {
      const Supernode& child = supernodes_[c];
      const int below = static_cast<int>(child.in_parent.size());
      for (int j = 0; j < below; ++j) {
        const int pj = 3 * child.in_parent[j];
        for (int i = j; i < below; ++i) {
          front.block<3, 3>(3 * child.in_parent[i], pj) += child.update.block<3, 3>(3 * i, 3 * j);
        }
      }
    }
    // Eliminate the supernode's columns: L11 L11^T = F11, L21 = F21 L11^-T, U = F22 - L21 L21^T.
    auto f11 = front.topLeftCorner(k, k);
    auto f21 = front.bottomLeftCorner(m - k, k);
    auto f22 = front.bottomRightCorner(m - k, m - k);
    Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>> cholesky(f11);
    if (cholesky.info() != Eigen::Success) return false;
    if (m > k) {
      f11.transpose().triangularView<Eigen::Upper>().solveInPlace<Eigen::OnTheRight>(f21);
      f22.selfadjointView<Eigen::Lower>().rankUpdate(f21, -1.0);
      s.update = f22;
    }
    s.panel = front.leftCols(k);
  }
  return true;
}

void SupernodalCholesky::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  for (int v = 0; v < num_vertices_; ++v) permuted_.segment<3>(3 * new_of_old_[v]) = b.segment<3>(3 * v);
  // Forward: L y = P b.
  for (const Supernode& s : supernodes_) {
    const int k = 3 * s.width;
    const int below = static_cast<int>(s.rows.size()) - s.width;
    auto y = permuted_.segment(3 * s.first, k);
    s.panel.topRows(k).triangularView<Eigen::Lower>().solveInPlace(y);
    if (below == 0) continue;
    auto gathered = gathered_.head(3 * below);
    gathered.noalias() = s.panel.bottomRows(3 * below) * y;
    for (int r = 0; r < below; ++r)
      permuted_.segment<3>(3 * s.rows[s.width + r]) -= gathered.segment<3>(3 * r);
  }
  // Backward: L^T z = y.
  for (auto it = supernodes_.rbegin(); it != supernodes_.rend(); ++it) {
    const Supernode& s = *it;
    const int k = 3 * s.width;
    const int below = static_cast<int>(s.rows.size()) - s.width;
    auto z = permuted_.segment(3 * s.first, k);
    if (below > 0) {
      auto gathered = gathered_.head(3 * below);
      for (int r = 0; r < below; ++r)
        gathered.segment<3>(3 * r) = permuted_.segment<3>(3 * s.rows[s.width + r]);
      z.noalias() -= s.panel.bottomRows(3 * below).transpose() * gathered;
    }
    s.panel.topRows(k).triangularView<Eigen::Lower>().transpose().solveInPlace(z);
  }
  x.resize(3 * num_vertices_);
  for (int v = 0; v < num_vertices_; ++v) x.segment<3>(3 * v) = permuted_.segment<3>(3 * new_of_old_[v]);
}

long SupernodalCholesky::factor_nonzeros() const {
  long total = 0;
  for (const Supernode& s : supernodes_) total += static_cast<long>(s.panel.rows()) * s.panel.cols();
  return total;
}

}  // namespace weft

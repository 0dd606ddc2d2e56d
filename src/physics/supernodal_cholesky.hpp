#pragma once
// Sparse Cholesky factorisation H = P^T L L^T P of a symmetric positive definite 3n x 3n matrix
// with 3x3 vertex blocks (a cloth's Hessian), by the multifrontal method on supernodes.
//
// Why not Eigen's SimplicialLDLT: it eliminates one scalar column at a time with indirect indexing
// per multiply-add. A supernode is a run of columns of L with the same row structure below them;
// its columns are eliminated together in one dense frontal matrix, so almost all the work becomes
// dense Cholesky, triangular solve and rank-k update (Eigen's blocked kernels). The ordering is
// AMD on the vertex graph, so the three coordinates of a vertex stay together.
//
// analyze() once per sparsity pattern (it sizes all storage), factorize() whenever the values
// change, solve() any number of times. factorize() returns false when the matrix is not positive
// definite (a non-positive pivot), which the Newton solver uses to detect an indefinite Hessian.
// Its fill and time against SimplicialLDLT: docs/integrators.md, "Which linear solver inside
// implicit Euler".
#include <vector>

#include <Eigen/Dense>
#include <Eigen/SparseCore>

namespace weft {

class SupernodalCholesky {
 public:
  using Matrix = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;

  // Symbolic analysis of the pattern of `matrix` (both triangles stored, 3x3 blocks).
  void analyze(const Matrix& matrix);
  // Numeric factorisation of a matrix with the analysed pattern; false if not positive definite.
  bool factorize(const Matrix& matrix);
  // x = H^{-1} b after a successful factorize(). x may alias b.
  void solve(const Eigen::VectorXd& b, Eigen::VectorXd& x);

  bool analyzed() const { return !supernodes_.empty(); }
  long factor_nonzeros() const;  // scalar entries of L, diagonal blocks counted in full
  int num_supernodes() const { return static_cast<int>(supernodes_.size()); }

 private:
  struct Supernode {
    int first = 0;    // first column vertex (in the eliminated order)
    int width = 0;    // column vertices: first .. first + width - 1
    int parent = -1;  // supernode that receives this one's update, -1 at a root
    std::vector<int> children;
    std::vector<int> rows;       // row vertices, eliminated order: the columns, then those below
    std::vector<int> in_parent;  // for each row below the columns: its row index in the parent
    // (value index in the matrix, position in the column-major front) of the entries it sums
    std::vector<std::pair<int, int>> assembly;
    Eigen::MatrixXd panel;   // 3 rows x 3 width: [L11; L21]
    Eigen::MatrixXd update;  // trailing Schur complement passed to the parent
  };

  int num_vertices_ = 0;
  std::vector<int> new_of_old_;  // vertex permutation
  std::vector<int> old_of_new_;
  std::vector<Supernode> supernodes_;  // in elimination order: children before parents
  Eigen::MatrixXd front_;              // scratch front, largest size
  Eigen::VectorXd permuted_, gathered_;
};

}  // namespace weft

#include "mcvio/estimator/marginalizer.hpp"

#include <algorithm>
#include <stdexcept>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "mcvio/estimator/pose_manifold.hpp"

namespace mcvio::estimator {

namespace {

int tangentSize(BlockKind kind, int size) { return kind == BlockKind::kPose ? 6 : size; }

// Symmetric pseudo-inverse; directions with tiny information are treated as unconstrained.
Eigen::MatrixXd pseudoInverse(const Eigen::MatrixXd& A) {
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(0.5 * (A + A.transpose()));
  const double eps = 1e-10 * std::max(1.0, es.eigenvalues().cwiseAbs().maxCoeff());
  const Eigen::VectorXd inv =
      es.eigenvalues().unaryExpr([eps](double l) { return l > eps ? 1.0 / l : 0.0; });
  return es.eigenvectors() * inv.asDiagonal() * es.eigenvectors().transpose();
}

// The same, Jacobi-scaled first, so the threshold is relative to each variable's own information:
// a dropped frame's velocity must not count as unconstrained next to its biases (1e11), or its
// coupling is never subtracted and the Schur complement claims information nobody has.
Eigen::MatrixXd scaledPseudoInverse(const Eigen::MatrixXd& A) {
  const Eigen::VectorXd s = A.diagonal().unaryExpr([](double h) { return h > 0 ? 1.0 / std::sqrt(h) : 0.0; });
  return s.asDiagonal() * pseudoInverse(s.asDiagonal() * A * s.asDiagonal()) * s.asDiagonal();
}

// Floor of the whole information's scaled LDL^T pivots (see marginalizeImpl).
constexpr double kWholeInformationFloor = 1e-13;

using CouplingBlock = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 3, 15>;
using PoseCoupling = Eigen::Matrix<double, 3, 6>;
// One eliminated landmark's normal equations. Fixed-size storage: the common 3-dof landmark seen
// from 6-dof poses never touches a dynamic-size matrix (it showed in the covariance's profile).
struct LandmarkTerms {
  int k = 0;  ///< landmark tangent size; h and g use their top k rows
  Eigen::Matrix3d h;
  Eigen::Vector3d g;
  std::vector<std::pair<int, PoseCoupling>> pose_coupling;    // dense offset -> H_landmark,pose (k == 3)
  std::vector<std::pair<int, CouplingBlock>> other_coupling;  // any other block width or k < 3

  void start(int size) {
    if (k != 0) return;
    k = size;
    h.setZero();
    g.setZero();
  }
  void addPose(int off, const PoseCoupling& c) {
    for (auto& [o, m] : pose_coupling)
      if (o == off) {
        m += c;
        return;
      }
    pose_coupling.emplace_back(off, c);
  }
};

}  // namespace

int Marginalizer::blockId(const double* data) const {
  const auto it = block_ids_by_data_.find(data);
  return it == block_ids_by_data_.end() ? -1 : it->second;
}

std::vector<char> Marginalizer::blockFlags(const std::set<const double*>& blocks) const {
  std::vector<char> flags(blocks_.size(), 0);
  for (const double* p : blocks) {
    const int id = blockId(p);
    if (id >= 0) flags[static_cast<std::size_t>(id)] = 1;
  }
  return flags;
}

void Marginalizer::addParameterBlock(double* data, BlockKind kind, int size) {
  const BlockInfo info{data, kind, size, tangentSize(kind, size)};
  const auto [it, inserted] = block_ids_by_data_.emplace(data, static_cast<int>(blocks_.size()));
  if (inserted)
    blocks_.push_back(info);
  else
    blocks_[static_cast<std::size_t>(it->second)] = info;
}

void Marginalizer::addResidualBlock(const ceres::CostFunction* cost, const ceres::LossFunction* loss,
                                    double* const* parameters, int num_parameters) {
  const int first = static_cast<int>(params_.size());
  for (int i = 0; i < num_parameters; ++i) {
    const int id = blockId(parameters[i]);
    if (id < 0) {
      params_.resize(static_cast<std::size_t>(first));
      block_ids_.resize(static_cast<std::size_t>(first));
      throw std::logic_error("Marginalizer: residual uses an unregistered parameter block");
    }
    params_.push_back(parameters[i]);
    block_ids_.push_back(id);
  }
  residuals_.push_back(Residual{cost, loss, first, num_parameters});
}

bool Marginalizer::linearize(const Residual& res, Eigen::VectorXd* r, std::vector<Eigen::MatrixXd>* J) const {
  const int m = res.cost->num_residuals();
  const auto& sizes = res.cost->parameter_block_sizes();
  r->resize(m);
  // Scratch buffers are reused across residuals: resizing to the same shape does not allocate.
  thread_local std::vector<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> Jg;
  thread_local std::vector<double*> jac_ptrs;
  if (Jg.size() < sizes.size()) Jg.resize(sizes.size());
  jac_ptrs.resize(sizes.size());
  for (std::size_t i = 0; i < sizes.size(); ++i) {
    Jg[i].resize(m, sizes[i]);
    jac_ptrs[i] = Jg[i].data();
  }
  if (!res.cost->Evaluate(&params_[static_cast<std::size_t>(res.first)], r->data(), jac_ptrs.data())) return false;
  if (J->size() != sizes.size()) J->resize(sizes.size());
  for (std::size_t i = 0; i < sizes.size(); ++i) {
    const BlockInfo& b = blocks_[static_cast<std::size_t>(block_ids_[static_cast<std::size_t>(res.first) + i])];
    Eigen::MatrixXd& Jt = (*J)[i];
    if (b.kind == BlockKind::kPose) {
      Jt.resize(m, 6);
      Jt.leftCols(3) = Jg[i].leftCols(3);
      Jt.rightCols(3).noalias() =
          Jg[i].rightCols(4) * PoseManifold::quaternionPlusJacobian(Eigen::Map<const Eigen::Quaterniond>(b.data + 3));
    } else {
      Jt = Jg[i];
    }
  }
  if (res.loss != nullptr) {
    double rho[3];
    res.loss->Evaluate(r->squaredNorm(), rho);
    const double s = std::sqrt(std::max(rho[1], 0.0));
    *r *= s;
    for (auto& j : *J) j *= s;
  }
  return r->allFinite();
}

void Marginalizer::reducedSystem(const std::vector<const double*>& order, const std::set<const double*>& drop,
                                 Eigen::MatrixXd* H, Eigen::VectorXd* g) const {
  std::vector<int> ids;
  ids.reserve(order.size());
  for (const double* p : order) {
    const int id = blockId(p);
    if (id < 0) throw std::logic_error("Marginalizer: unregistered parameter block in the order");
    ids.push_back(id);
  }
  reduce(ids, blockFlags(drop), H, g);
}

void Marginalizer::reduce(const std::vector<int>& order, const std::vector<char>& dropped, Eigen::MatrixXd* H,
                          Eigen::VectorXd* g) const {
  auto isDropped = [&](int id) { return dropped[static_cast<std::size_t>(id)] != 0; };
  auto isEliminated = [&](int id) {
    return isDropped(id) && blocks_[static_cast<std::size_t>(id)].kind == BlockKind::kLandmark;
  };
  std::vector<int> offset(blocks_.size(), -1);
  int dim = 0;
  for (const int id : order) {
    offset[static_cast<std::size_t>(id)] = dim;
    dim += blocks_[static_cast<std::size_t>(id)].tangent_size;
  }
  H->setZero(dim, dim);
  g->setZero(dim);
  auto offsetOf = [&](int id) {
    const int o = offset[static_cast<std::size_t>(id)];
    if (o < 0) throw std::logic_error("Marginalizer: a residual uses a block outside the order");
    return o;
  };

  // Terms in first-use order, so the elimination (and its rounding) does not depend on addresses.
  // The storage is reused across calls: a covariance per frame must not allocate per landmark.
  thread_local std::vector<LandmarkTerms> terms;
  std::size_t n_terms = 0;
  std::vector<int> slot(blocks_.size(), -1);
  auto termsOf = [&](int id) -> LandmarkTerms& {
    int& s = slot[static_cast<std::size_t>(id)];
    if (s < 0) {
      s = static_cast<int>(n_terms++);
      if (terms.size() < n_terms) terms.emplace_back();
      LandmarkTerms& t = terms[static_cast<std::size_t>(s)];
      t.k = 0;
      t.pose_coupling.clear();
      t.other_coupling.clear();
    }
    return terms[static_cast<std::size_t>(s)];
  };

  Eigen::VectorXd r;
  std::vector<Eigen::MatrixXd> J;
  std::vector<int> offs;
  for (const auto& res : residuals_) {
    double* const* params = &params_[static_cast<std::size_t>(res.first)];
    const int* ids = &block_ids_[static_cast<std::size_t>(res.first)];
    const bool two_rows = res.cost->num_residuals() == 2;
    // Fixed-size fast path for the dominant visual residual: 2 rows over
    // [pose, pose, eliminated 3-dof landmark].
    if (two_rows && res.count == 3 && isEliminated(ids[2])) {
      const BlockInfo& b0 = blocks_[static_cast<std::size_t>(ids[0])];
      const BlockInfo& b1 = blocks_[static_cast<std::size_t>(ids[1])];
      const BlockInfo& b2 = blocks_[static_cast<std::size_t>(ids[2])];
      if (b0.kind == BlockKind::kPose && b1.kind == BlockKind::kPose && b2.size == 3 && !isDropped(ids[0]) &&
          !isDropped(ids[1])) {
        Eigen::Matrix<double, 2, 7, Eigen::RowMajor> G0, G1;
        Eigen::Matrix<double, 2, 3, Eigen::RowMajor> G2;
        Eigen::Vector2d rr;
        double* jp[3] = {G0.data(), G1.data(), G2.data()};
        if (!res.cost->Evaluate(params, rr.data(), jp) || !rr.allFinite())
          throw std::logic_error("Marginalizer: a residual block could not be evaluated");
        Eigen::Matrix<double, 2, 6> J0, J1;
        Eigen::Matrix<double, 2, 3> J2 = G2;
        J0.leftCols<3>() = G0.leftCols<3>();
        J0.rightCols<3>() = G0.rightCols<4>() * PoseManifold::quaternionPlusJacobian(Eigen::Map<const Eigen::Quaterniond>(b0.data + 3));
        J1.leftCols<3>() = G1.leftCols<3>();
        J1.rightCols<3>() = G1.rightCols<4>() * PoseManifold::quaternionPlusJacobian(Eigen::Map<const Eigen::Quaterniond>(b1.data + 3));
        if (res.loss != nullptr) {
          double rho[3];
          res.loss->Evaluate(rr.squaredNorm(), rho);
          const double sc = std::sqrt(std::max(rho[1], 0.0));
          rr *= sc;
          J0 *= sc;
          J1 *= sc;
          J2 *= sc;
        }
        const int o0 = offsetOf(ids[0]), o1 = offsetOf(ids[1]);
        H->block<6, 6>(o0, o0).noalias() += J0.transpose() * J0;
        // Two-term sums: J1^T J0 is exactly the transpose of J0^T J1.
        const Eigen::Matrix<double, 6, 6> h01 = J0.transpose() * J1;
        H->block<6, 6>(o0, o1) += h01;
        H->block<6, 6>(o1, o0) += h01.transpose();
        H->block<6, 6>(o1, o1).noalias() += J1.transpose() * J1;
        g->segment<6>(o0).noalias() += J0.transpose() * rr;
        g->segment<6>(o1).noalias() += J1.transpose() * rr;
        LandmarkTerms& t = termsOf(ids[2]);
        t.start(3);
        t.h.noalias() += J2.transpose() * J2;
        t.g.noalias() += J2.transpose() * rr;
        t.addPose(o0, J2.transpose() * J0);
        t.addPose(o1, J2.transpose() * J1);
        continue;
      }
    }
    // Fixed-size fast path for a landmark's observation in its anchor frame: 2 rows over the
    // eliminated 3-dof landmark only.
    if (two_rows && res.count == 1 && isEliminated(ids[0]) &&
        blocks_[static_cast<std::size_t>(ids[0])].size == 3) {
      Eigen::Matrix<double, 2, 3, Eigen::RowMajor> G;
      Eigen::Vector2d rr;
      double* jp[1] = {G.data()};
      if (!res.cost->Evaluate(params, rr.data(), jp))
        throw std::logic_error("Marginalizer: a residual block could not be evaluated");
      Eigen::Matrix<double, 2, 3> Jl = G;
      if (res.loss != nullptr) {
        double rho[3];
        res.loss->Evaluate(rr.squaredNorm(), rho);
        const double sc = std::sqrt(std::max(rho[1], 0.0));
        rr *= sc;
        Jl *= sc;
      }
      if (!rr.allFinite()) throw std::logic_error("Marginalizer: a residual block could not be evaluated");
      LandmarkTerms& t = termsOf(ids[0]);
      t.start(3);
      t.h.noalias() += Jl.transpose() * Jl;
      t.g.noalias() += Jl.transpose() * rr;
      continue;
    }
    if (!linearize(res, &r, &J)) throw std::logic_error("Marginalizer: a residual block could not be evaluated");
    int li = -1;
    offs.assign(static_cast<std::size_t>(res.count), -1);
    for (int a = 0; a < res.count; ++a) {
      const BlockInfo& b = blocks_[static_cast<std::size_t>(ids[a])];
      if (isEliminated(ids[a])) {
        if (li >= 0) throw std::logic_error("Marginalizer: a residual touches two eliminated landmarks");
        if (b.tangent_size > 3) throw std::logic_error("Marginalizer: landmark blocks have at most 3 dimensions");
        li = a;
      } else {
        offs[static_cast<std::size_t>(a)] = offsetOf(ids[a]);
      }
    }
    for (std::size_t a = 0; a < offs.size(); ++a) {
      if (offs[a] < 0) continue;
      const auto na = J[a].cols();
      g->segment(offs[a], na).noalias() += J[a].transpose() * r;
      for (std::size_t b = 0; b < offs.size(); ++b) {
        if (offs[b] < 0) continue;
        H->block(offs[a], offs[b], na, J[b].cols()).noalias() += J[a].transpose() * J[b];
      }
    }
    if (li >= 0) {
      LandmarkTerms& t = termsOf(ids[li]);
      const Eigen::MatrixXd& Jl = J[static_cast<std::size_t>(li)];
      const auto k = static_cast<int>(Jl.cols());
      t.start(k);
      if (t.k != k) throw std::logic_error("Marginalizer: a landmark block changed size");
      t.h.topLeftCorner(k, k).noalias() += Jl.transpose() * Jl;
      t.g.head(k).noalias() += Jl.transpose() * r;
      for (std::size_t a = 0; a < offs.size(); ++a) {
        if (offs[a] < 0) continue;
        if (J[a].cols() > 15) throw std::logic_error("Marginalizer: block coupled to a landmark is too large");
        if (k == 3 && J[a].cols() == 6) {
          t.addPose(offs[a], Jl.transpose() * J[a]);
          continue;
        }
        auto it = std::find_if(t.other_coupling.begin(), t.other_coupling.end(),
                               [&](const auto& c) { return c.first == offs[a]; });
        if (it == t.other_coupling.end()) {
          t.other_coupling.emplace_back(offs[a], CouplingBlock::Zero(k, J[a].cols()));
          it = t.other_coupling.end() - 1;
        }
        it->second.noalias() += Jl.transpose() * J[a];
      }
    }
  }
  // Exact Schur complement of each landmark (no residual couples two of them).
  for (std::size_t i = 0; i < n_terms; ++i) {
    const LandmarkTerms& t = terms[i];
    if (t.k == 3 && t.other_coupling.empty()) {
      // 3-dof landmark coupled to poses only: fixed-size arithmetic.
      Eigen::Matrix3d h_inv;
      Eigen::LLT<Eigen::Matrix3d> llt(t.h);
      // A landmark left with one observation has a rank-2 h; its Cholesky "succeeds" on a last
      // pivot of rounding noise, and the inverse of that noise made the window's information
      // indefinite (covariance reported invalid). Such landmarks take the pseudo-inverse, which
      // is exact for them: their coupling lies in the range of h.
      const double min_pivot = llt.info() == Eigen::Success ? llt.matrixLLT().diagonal().minCoeff() : 0.0;
      if (llt.info() == Eigen::Success && t.h.diagonal().minCoeff() > 1e-12 &&
          min_pivot * min_pivot > 1e-10 * t.h.diagonal().maxCoeff())
        h_inv = llt.solve(Eigen::Matrix3d::Identity());
      else
        h_inv = pseudoInverse(Eigen::MatrixXd(t.h));
      const auto& c = t.pose_coupling;
      for (std::size_t a = 0; a < c.size(); ++a) {
        const int oa = c[a].first;
        const Eigen::Matrix<double, 6, 3> cah = c[a].second.transpose() * h_inv;
        g->segment<6>(oa).noalias() -= cah * t.g;
        for (std::size_t b = a; b < c.size(); ++b) {
          const int ob = c[b].first;
          const Eigen::Matrix<double, 6, 6> s = cah * c[b].second;
          H->block<6, 6>(oa, ob) -= s;
          // The update is symmetric: the mirrored block needs no product of its own.
          if (b != a) H->block<6, 6>(ob, oa) -= s.transpose();
        }
      }
      continue;
    }
    const int k = t.k;
    std::vector<std::pair<int, CouplingBlock>> coupling = t.other_coupling;
    for (const auto& [o, m] : t.pose_coupling) coupling.emplace_back(o, m);
    const Eigen::MatrixXd h_inv = pseudoInverse(Eigen::MatrixXd(t.h.topLeftCorner(k, k)));
    const Eigen::VectorXd tg = t.g.head(k);
    for (const auto& [oa, ca] : coupling) {
      const Eigen::MatrixXd cah = ca.transpose() * h_inv;
      g->segment(oa, ca.cols()) -= cah * tg;
      for (const auto& [ob, cb] : coupling) H->block(oa, ob, ca.cols(), cb.cols()) -= cah * cb;
    }
  }
}

std::shared_ptr<MarginalizationPrior> Marginalizer::marginalize(const std::set<const double*>& drop) const {
  return marginalizeImpl(drop, nullptr, nullptr, false).prior;
}

Marginalizer::SplitPrior Marginalizer::marginalizeSplit(const std::set<const double*>& drop,
                                                        const MarginalizationPrior* whole_in,
                                                        const ceres::CostFunction* prior_in) const {
  return marginalizeImpl(drop, whole_in, prior_in, true);
}

Marginalizer::SplitPrior Marginalizer::marginalizeImpl(const std::set<const double*>& drop,
                                                       const MarginalizationPrior* whole_in,
                                                       const ceres::CostFunction* prior_in, bool want_whole) const {
  // Dense order: dropped non-landmark blocks first, then the kept ones (in first-use order).
  const std::vector<char> dropped_flag = blockFlags(drop);
  std::vector<int> dropped, kept;
  std::vector<char> seen(blocks_.size(), 0);
  for (const int id : block_ids_) {
    const auto i = static_cast<std::size_t>(id);
    if (seen[i] != 0) continue;
    seen[i] = 1;
    if (dropped_flag[i] != 0) {
      if (blocks_[i].kind != BlockKind::kLandmark) dropped.push_back(id);
    } else {
      kept.push_back(id);
    }
  }
  if (kept.empty()) return {};
  std::vector<int> order = dropped;
  order.insert(order.end(), kept.begin(), kept.end());
  Eigen::MatrixXd H;
  Eigen::VectorXd g;
  reduce(order, dropped_flag, &H, &g);
  int m = 0;
  for (const int id : dropped) m += blocks_[static_cast<std::size_t>(id)].tangent_size;
  const int n = static_cast<int>(H.rows()) - m;
  std::vector<int> offset(blocks_.size(), -1);
  {
    int dim = 0;
    for (const int id : order) {
      offset[static_cast<std::size_t>(id)] = dim;
      dim += blocks_[static_cast<std::size_t>(id)].tangent_size;
    }
  }

  Eigen::MatrixXd Hs = H.bottomRightCorner(n, n);
  Eigen::VectorXd gs = g.tail(n);
  if (m > 0) {
    const Eigen::MatrixXd Hmm_inv = pseudoInverse(H.topLeftCorner(m, m));
    const Eigen::MatrixXd Hnm = H.bottomLeftCorner(n, m);
    Hs -= Hnm * Hmm_inv * Hnm.transpose();
    gs -= Hnm * Hmm_inv * g.head(m);
  }
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(0.5 * (Hs + Hs.transpose()));
  // Directions known to less than 1e-8 of the strongest (a bias, near 1e11) leave the prior: that
  // is anything known worse than about 3 cm, the absolute position and yaw included once the drift
  // passes that. Keeping them in the optimisation (1e-11: the covariance keeps its gauge, ATE -10 %
  // at feature level) costs MC-VIO at image level (overlay 0.070 -> 0.104 m, slow object 0.046 ->
  // 0.068 m), so only the covariance's whole information keeps them. README "Consistency and the
  // prior's floor" has the measurements.
  const double max_eigenvalue = std::max(1.0, es.eigenvalues().maxCoeff());
  const double eps = 1e-8 * max_eigenvalue;
  std::vector<int> rows;
  for (int i = 0; i < n; ++i)
    if (es.eigenvalues()[i] > eps) rows.push_back(i);

  auto prior = std::make_shared<MarginalizationPrior>();
  prior->J.resize(static_cast<int>(rows.size()), n);
  prior->r.resize(static_cast<int>(rows.size()));
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const int i = rows[k];
    const double s = std::sqrt(es.eigenvalues()[i]);
    prior->J.row(static_cast<int>(k)) = s * es.eigenvectors().col(i).transpose();
    prior->r[static_cast<int>(k)] = es.eigenvectors().col(i).dot(gs) / s;
  }
  for (const int id : kept) {
    const BlockInfo& b = blocks_[static_cast<std::size_t>(id)];
    MarginalizationPrior::Block blk;
    blk.data = b.data;
    blk.kind = b.kind == BlockKind::kLandmark ? BlockKind::kEuclidean : b.kind;
    blk.size = b.size;
    blk.tangent_size = b.tangent_size;
    blk.x_lin.assign(b.data, b.data + b.size);
    prior->blocks.push_back(std::move(blk));
  }
  SplitPrior out;
  out.prior = prior;
  if (!want_whole) return out;

  // The whole information: the same system with the optimisation's prior replaced by the whole
  // information it was cut from. Subtracting the prior's own terms (the very numbers reduce() added)
  // is exact to rounding of each entry; a difference of eigen-decompositions is not: its error, a
  // fraction of the biases' 1e11, buried the gauge's few units of information (README).
  Eigen::MatrixXd Hf = H;
  if (whole_in != nullptr && prior_in != nullptr) {
    const auto it = std::find_if(residuals_.begin(), residuals_.end(), [&](const Residual& r) { return r.cost == prior_in; });
    if (it == residuals_.end()) throw std::logic_error("Marginalizer: the replaced prior is not among the residuals");
    Eigen::VectorXd r;
    std::vector<Eigen::MatrixXd> J;
    if (!linearize(*it, &r, &J)) throw std::logic_error("Marginalizer: a residual block could not be evaluated");
    for (int a = 0; a < it->count; ++a) {
      const int oa = offset[static_cast<std::size_t>(block_ids_[static_cast<std::size_t>(it->first + a)])];
      for (int b = 0; b < it->count; ++b) {
        const int ob = offset[static_cast<std::size_t>(block_ids_[static_cast<std::size_t>(it->first + b)])];
        Hf.block(oa, ob, J[a].cols(), J[b].cols()).noalias() -= J[a].transpose() * J[b];
      }
    }
    const Eigen::MatrixXd info = whole_in->information();
    std::vector<std::pair<int, int>> cols;  // (offset in H, offset in whole_in) per block
    int col = 0;
    for (const auto& b : whole_in->blocks) {
      const int id = blockId(b.data);
      if (id < 0 || offset[static_cast<std::size_t>(id)] < 0)
        throw std::logic_error("Marginalizer: the whole prior uses a block outside the marginalisation");
      cols.emplace_back(offset[static_cast<std::size_t>(id)], col);
      col += b.tangent_size;
    }
    for (std::size_t a = 0; a < cols.size(); ++a)
      for (std::size_t b = 0; b < cols.size(); ++b)
        Hf.block(cols[a].first, cols[b].first, whole_in->blocks[a].tangent_size, whole_in->blocks[b].tangent_size) +=
            info.block(cols[a].second, cols[b].second, whole_in->blocks[a].tangent_size, whole_in->blocks[b].tangent_size);
  }
  Eigen::MatrixXd Hs_whole = Hf.bottomRightCorner(n, n);
  if (m > 0) {
    const Eigen::MatrixXd Hnm = Hf.bottomLeftCorner(n, m);
    Hs_whole -= Hnm * scaledPseudoInverse(Hf.topLeftCorner(m, m)) * Hnm.transpose();
  }
  // Jacobi-scaled, so the floor is relative to each variable's own information and not to a bias's;
  // a pivoted LDL^T factors it several times cheaper than an eigen-decomposition.
  const Eigen::VectorXd inv_scale =
      Hs_whole.diagonal().unaryExpr([](double h) { return h > 0 ? 1.0 / std::sqrt(h) : 1.0; });
  const Eigen::MatrixXd scaled = inv_scale.asDiagonal() * (0.5 * (Hs_whole + Hs_whole.transpose())) * inv_scale.asDiagonal();
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(scaled);
  // Scaled, the rounding is of order n * 2e-16 (an estimate, ~1e-14 here).
  const double eps_whole = kWholeInformationFloor;
  const Eigen::VectorXd d = ldlt.vectorD();
  std::vector<int> whole_rows;
  for (int i = 0; i < n; ++i)
    if (d[i] > eps_whole) whole_rows.push_back(i);
  if (whole_rows.empty()) return out;
  // scaled = P^T L D L^T P: the rows of sqrt(D) L^T P, unscaled, are a square root of Hs_whole.
  const Eigen::MatrixXd LtP = Eigen::MatrixXd(ldlt.matrixU()) * ldlt.transpositionsP().transpose() *
                              inv_scale.cwiseInverse().asDiagonal();
  auto whole = std::make_shared<MarginalizationPrior>();
  whole->blocks = prior->blocks;
  whole->J.resize(static_cast<int>(whole_rows.size()), n);
  whole->r = Eigen::VectorXd::Zero(static_cast<int>(whole_rows.size()));
  for (std::size_t k = 0; k < whole_rows.size(); ++k) {
    const int i = whole_rows[k];
    whole->J.row(static_cast<int>(k)) = std::sqrt(d[i]) * LtP.row(i);
  }
  out.whole = std::move(whole);
  return out;
}

bool Marginalizer::marginalCovariance(const double* block, Eigen::MatrixXd* covariance) const {
  return marginalCovariance(std::vector<const double*>{block}, covariance);
}

bool Marginalizer::marginalCovariance(const std::vector<const double*>& blocks, Eigen::MatrixXd* covariance) const {
  std::vector<int> wanted;
  for (const double* b : blocks) wanted.push_back(blockId(b));
  std::vector<int> order;
  std::vector<char> dropped(blocks_.size(), 0), seen(blocks_.size(), 0);
  std::vector<int> start(blocks_.size(), -1);
  int dim = 0;
  for (const int id : block_ids_) {
    const auto i = static_cast<std::size_t>(id);
    if (seen[i] != 0) continue;
    seen[i] = 1;
    if (blocks_[i].kind == BlockKind::kLandmark) {
      dropped[i] = 1;
      continue;
    }
    start[i] = dim;
    order.push_back(id);
    dim += blocks_[i].tangent_size;
  }
  int k = 0;
  for (const int id : wanted) {
    if (id < 0 || start[static_cast<std::size_t>(id)] < 0) return false;
    k += blocks_[static_cast<std::size_t>(id)].tangent_size;
  }
  Eigen::MatrixXd H;
  Eigen::VectorXd g;
  reduce(order, dropped, &H, &g);
  Eigen::LLT<Eigen::MatrixXd> llt(0.5 * (H + H.transpose()));
  if (llt.info() != Eigen::Success) return false;
  Eigen::MatrixXd E = Eigen::MatrixXd::Zero(H.rows(), k);
  int col = 0;
  for (const int id : wanted) {
    const int size = blocks_[static_cast<std::size_t>(id)].tangent_size;
    E.block(start[static_cast<std::size_t>(id)], col, size, size).setIdentity();
    col += size;
  }
  const Eigen::MatrixXd X = llt.solve(E);
  covariance->resize(k, k);
  col = 0;
  for (const int id : wanted) {
    const int size = blocks_[static_cast<std::size_t>(id)].tangent_size;
    covariance->middleRows(col, size) = X.middleRows(start[static_cast<std::size_t>(id)], size);
    col += size;
  }
  *covariance = 0.5 * (*covariance + covariance->transpose());
  return covariance->allFinite();
}

}  // namespace mcvio::estimator

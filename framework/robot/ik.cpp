#include "cluttertamp/robot/ik.hpp"

#include <algorithm>
#include <optional>
#include <cmath>
#include <random>
#include <stdexcept>

#include <Eigen/Geometry>

namespace cluttertamp::robot {

namespace {

constexpr double kPi = M_PI;

// Standard DH link transform A(theta) = Rz(theta) Tz(d) Tx(a) Rx(alpha).
Eigen::Isometry3d dh_transform(double theta, double d, double a, double alpha) {
  const double ct = std::cos(theta), st = std::sin(theta), ca = std::cos(alpha), sa = std::sin(alpha);
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() << ct, -st * ca, st * sa, st, ct * ca, -ct * sa, 0, sa, ca;
  t.translation() << a * ct, a * st, d;
  return t;
}

double wrap(double angle) {
  angle = std::remainder(angle, 2 * kPi);
  return angle <= -kPi ? angle + 2 * kPi : angle;
}

// acos that tolerates rounding just outside [-1, 1]; nullopt when truly outside.
std::optional<double> safe_acos(double x) {
  if (x > 1.0 + 1e-10 || x < -1.0 - 1e-10) return std::nullopt;
  return std::acos(std::clamp(x, -1.0, 1.0));
}

// The angle + 2 pi k inside the joint's limits that is nearest to `near`.
std::optional<double> fit_limits(double angle, const Joint& joint, double near) {
  std::optional<double> best;
  for (int k = -3; k <= 3; ++k) {
    const double value = angle + 2 * kPi * k;
    if (value < joint.lower - 1e-12 || value > joint.upper + 1e-12) continue;
    if (!best || std::abs(value - near) < std::abs(*best - near)) best = std::clamp(value, joint.lower, joint.upper);
  }
  return best;
}

// Largest joint difference, with continuous joints compared modulo 2 pi.
double joint_distance(const RobotModel& model, const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  double worst = 0.0;
  for (std::size_t i = 0; i < model.variable_count(); ++i) {
    const Joint& joint = model.joints()[model.variables()[i]];
    double d = a[static_cast<Eigen::Index>(i)] - b[static_cast<Eigen::Index>(i)];
    if (joint.continuous) d = std::remainder(d, 2 * kPi);
    worst = std::max(worst, std::abs(d));
  }
  return worst;
}

void check_seed(const RobotModel& model, const Eigen::VectorXd& seed) {
  if (static_cast<std::size_t>(seed.size()) != model.variable_count()) {
    throw std::invalid_argument("IK: the seed configuration has " + std::to_string(seed.size()) + " values, the robot " +
                                std::to_string(model.variable_count()));
  }
}

// Solutions nearest the seed first.
void sort_by_seed(const RobotModel& model, const Eigen::VectorXd& seed, std::vector<Eigen::VectorXd>& solutions) {
  std::stable_sort(solutions.begin(), solutions.end(), [&](const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
    return (a - seed).squaredNorm() < (b - seed).squaredNorm();
  });
  (void)model;
}

bool near(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double tolerance = 1e-9) {
  return a.matrix().isApprox(b.matrix(), tolerance) || (a.matrix() - b.matrix()).cwiseAbs().maxCoeff() < tolerance;
}

Eigen::Isometry3d rx(double angle) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitX()).toRotationMatrix();
  return t;
}

Eigen::Isometry3d translation(double x, double y, double z) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() << x, y, z;
  return t;
}

bool contains_close(const RobotModel& model, const std::vector<Eigen::VectorXd>& set, const Eigen::VectorXd& q,
                    double tolerance) {
  return std::any_of(set.begin(), set.end(), [&](const Eigen::VectorXd& s) { return joint_distance(model, s, q) < tolerance; });
}

}  // namespace

std::pair<double, double> pose_error(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  const double position = (a.translation() - b.translation()).norm();
  const double orientation = Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle();
  return {position, orientation};
}

IkSolver::~IkSolver() = default;

IkSolver::IkSolver(std::shared_ptr<const RobotModel> model, LinkIndex base, LinkIndex tip)
    : model_(std::move(model)), base_(base), tip_(tip) {
  chain_ = model_->chain(base, tip);
  for (LinkIndex current = tip; current != base;) {
    const JointIndex j = model_->links()[current].parent_joint;
    if (model_->joints()[j].mimicked >= 0) {
      throw std::invalid_argument("IK: joint '" + model_->joints()[j].name + "' on the chain mimics another joint");
    }
    path_.push_back(j);
    current = model_->joints()[j].parent;
  }
  std::reverse(path_.begin(), path_.end());
}

Eigen::Isometry3d IkSolver::forward(const Eigen::VectorXd& q) const {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  for (JointIndex j : path_) {
    const Joint& joint = model_->joints()[j];
    t = t * RobotModel::joint_transform(joint, joint.value(q, model_->joints()));
  }
  return t;
}

IkSolver::Reach IkSolver::reach() const {
  const auto& joints = model_->joints();
  Reach reach;
  Eigen::Isometry3d before = Eigen::Isometry3d::Identity();  // base to the first movable joint
  bool moving = false;
  for (JointIndex j : path_) {
    const Joint& joint = joints[j];
    if (!moving) {
      before = before * joint.parent_T_joint;
      if (joint.type == JointType::fixed) continue;
      moving = true;
      reach.centre = before.translation();
    } else {
      reach.radius += joint.parent_T_joint.translation().norm();
    }
    if (joint.type == JointType::prismatic) reach.radius += std::max(std::abs(joint.lower), std::abs(joint.upper));
  }
  if (!moving) reach.centre = before.translation();  // nothing moves: the tip stays put
  return reach;
}

// ---------------------------------------------------------------------------------
// UR analytic IK (the closed form of Hawkins, "Analytic inverse kinematics for the
// Universal Robots UR-5/UR-10 arms", 2013, for joints 1, 5 and 6; joints 2 to 4 as a
// planar 2R arm plus the remaining rotation), on DH parameters read from the model.

namespace {

Eigen::Isometry3d rz(double angle) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return t;
}

// A fixed transform between two joints whose axes are both z, written as
// Rz(gamma) Tz(d) Tx(a) Rx(alpha) Tz(e) Rz(delta): DH's link transform with what
// slides along, or turns about, either axis split off (those become joint offsets and
// shifts along the axes).
struct AxisLink {
  double gamma = 0, d = 0, a = 0, e = 0, delta = 0;
};

// `link` as an AxisLink with twist `alpha` (0 for parallel axes, +-pi/2 for
// perpendicular ones); nothing when the axes do not stand so.
std::optional<AxisLink> split_link(const Eigen::Isometry3d& link, double alpha) {
  constexpr double kTolerance = 1e-6;
  const Eigen::Vector3d z = Eigen::Vector3d::UnitZ(), next_z = link.linear().col(2), p = link.translation();
  Eigen::Vector3d x;
  if (alpha == 0.0) {
    if ((next_z - z).norm() > kTolerance) return std::nullopt;
    // The common normal's direction is free up to its sign: x itself where it will do,
    // so that a DH layout written as such reads back unchanged (a < 0 included).
    x = std::abs(p.y()) < kTolerance ? Eigen::Vector3d::UnitX() : Eigen::Vector3d(p.x(), p.y(), 0).normalized();
  } else {
    if (std::abs(next_z.dot(z)) > kTolerance) return std::nullopt;
    x = (alpha > 0 ? 1.0 : -1.0) * z.cross(next_z).normalized();
  }
  AxisLink out;
  out.gamma = std::atan2(x.y(), x.x());
  out.d = p.dot(z);
  out.a = p.dot(x);
  const Eigen::Isometry3d rest = (rz(out.gamma) * translation(0, 0, out.d) * translation(out.a, 0, 0) * rx(alpha)).inverse() * link;
  if (rest.translation().head<2>().norm() > kTolerance || std::abs(rest.linear()(2, 2) - 1) > kTolerance) return std::nullopt;
  out.e = rest.translation().z();
  out.delta = std::atan2(rest.linear()(1, 0), rest.linear()(0, 0));
  return out;
}

}  // namespace

UrAnalyticIk::UrAnalyticIk(std::shared_ptr<const RobotModel> model, LinkIndex base, LinkIndex tip)
    : IkSolver(std::move(model), base, tip) {
  const auto& joints = model_->joints();
  if (chain_.size() != 6) {
    throw std::invalid_argument("ur_analytic IK needs a chain of 6 movable joints; this one has " +
                                std::to_string(chain_.size()));
  }
  for (JointIndex j : chain_) {
    if (joints[j].type != JointType::revolute) {
      throw std::invalid_argument("ur_analytic IK: joint '" + joints[j].name + "' must be revolute");
    }
  }
  // Each joint's axis is turned onto z (URDFs put it anywhere: the makers' UR files use
  // y), either way round: 64 choices of direction, of which the UR layout admits those
  // where the links split as DH's with twists pi/2, 0, 0, pi/2, -pi/2.
  for (unsigned directions = 0; directions < 64; ++directions) {
    if (adopt_layout(directions)) return;
  }
  throw std::invalid_argument("ur_analytic IK: the joints of '" + joints[chain_.front()].name + "' to '" +
                              joints[chain_.back()].name +
                              "' do not stand as a UR arm's (axes 2 to 4 parallel, 1 and 5 perpendicular to them, "
                              "6 perpendicular to 5, with offsets only where a UR arm has them)");
}

bool UrAnalyticIk::adopt_layout(unsigned directions) {
  const auto& joints = model_->joints();
  // Fixed transforms: before joint 1, between consecutive joints (joint origin plus any
  // fixed joints in between, the axes turned onto z), and after joint 6.
  std::vector<Eigen::Isometry3d> between(7, Eigen::Isometry3d::Identity());
  std::size_t slot = 0;
  for (JointIndex j : path_) {
    const Joint& joint = joints[j];
    between[slot] = between[slot] * joint.parent_T_joint;
    if (joint.type == JointType::fixed) continue;
    signs_[slot] = (directions >> slot) & 1U ? -1.0 : 1.0;
    Eigen::Isometry3d onto_axis = Eigen::Isometry3d::Identity();
    onto_axis.linear() = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), signs_[slot] * joint.axis.normalized())
                             .toRotationMatrix();
    between[slot] = between[slot] * onto_axis;
    between[++slot] = onto_axis.inverse();
  }
  const double twist[5] = {kPi / 2, 0, 0, kPi / 2, -kPi / 2};
  AxisLink link[5];
  for (int k = 0; k < 5; ++k) {
    const auto split = split_link(between[k + 1], twist[k]);
    if (!split) return false;
    link[k] = *split;
  }
  constexpr double kTolerance = 1e-6;
  if (std::abs(link[0].a) > kTolerance || std::abs(link[3].a) > kTolerance || std::abs(link[4].a) > kTolerance) return false;
  if (std::abs(link[1].a) < kTolerance || std::abs(link[2].a) < kTolerance) return false;
  // Shifts along an axis commute with its rotation: those along the parallel axes 2 to
  // 4 all join d4, those along axis 5 join d5, those along axis 6 the flange.
  dh_ = {link[0].d, link[1].a, link[2].a,
         link[0].e + link[1].d + link[1].e + link[2].d + link[2].e + link[3].d,
         link[3].e + link[4].d, 0.0};
  offsets_[0] = link[0].gamma;
  for (int k = 1; k < 5; ++k) offsets_[k] = link[k - 1].delta + link[k].gamma;
  offsets_[5] = link[4].delta;
  // A shift along axis 1 before it commutes with it too: d1 counts from the foot of the
  // base's origin on axis 1, as DH's base frame does.
  const double along_axis1 = between[0].linear().col(2).dot(between[0].translation());
  dh_.d1 += along_axis1;
  base_T_joint1_ = between[0] * translation(0, 0, -along_axis1);
  flange_T_tip_ = translation(0, 0, link[4].e) * between[6];
  dh_.d6 = flange_T_tip_.translation().z();
  return reproduces_forward_kinematics();
}

// The layout found must give the model's own forward kinematics: checked on
// configurations spread over the joints' ranges (deterministic).
bool UrAnalyticIk::reproduces_forward_kinematics() const {
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> angle(-kPi, kPi);
  const double alpha[6] = {kPi / 2, 0, 0, kPi / 2, -kPi / 2, 0};
  const double d[6] = {dh_.d1, 0, 0, dh_.d4, dh_.d5, 0};
  const double a[6] = {0, dh_.a2, dh_.a3, 0, 0, 0};
  Eigen::VectorXd q = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(model_->variable_count()));
  for (int trial = 0; trial < 8; ++trial) {
    Eigen::Isometry3d dh = base_T_joint1_;
    for (int i = 0; i < 6; ++i) {
      const double value = trial == 0 ? 0.0 : angle(rng);
      q[model_->joints()[chain_[i]].variable] = value;
      dh = dh * dh_transform(signs_[i] * value + offsets_[i], d[i], a[i], alpha[i]);
    }
    dh = dh * flange_T_tip_;
    if (!near(dh, forward(q), 1e-6)) return false;  // split_link's tolerance
  }
  return true;
}

std::vector<Eigen::VectorXd> UrAnalyticIk::solve(const Eigen::Isometry3d& base_T_tip,
                                                 const Eigen::VectorXd& seed_configuration, std::uint64_t) const {
  check_seed(*model_, seed_configuration);
  const auto [d1, a2, a3, d4, d5, d6_unused] = dh_;
  (void)d6_unused;
  // A virtual flange one metre along the sixth axis keeps the closed form valid for
  // any tool transform (the formulas divide by d6).
  constexpr double d6 = 1.0;
  const Eigen::Isometry3d T = base_T_joint1_.inverse() * base_T_tip * flange_T_tip_.inverse() * translation(0, 0, d6);
  const Eigen::Matrix4d& m = T.matrix();
  const Eigen::Isometry3d T_inv = T.inverse();
  const Eigen::Matrix4d& mi = T_inv.matrix();

  std::vector<Eigen::VectorXd> solutions;
  const Eigen::Vector3d p05 = (T * Eigen::Vector3d(0, 0, -d6));
  const double r = std::hypot(p05.x(), p05.y());
  const auto phi = safe_acos(r > 0 ? d4 / r : 2.0);
  if (!phi) return solutions;
  const double psi = std::atan2(p05.y(), p05.x());
  for (double theta1 : {psi + *phi + kPi / 2, psi - *phi + kPi / 2}) {
    const double s1 = std::sin(theta1), c1 = std::cos(theta1);
    const auto acos5 = safe_acos((m(0, 3) * s1 - m(1, 3) * c1 - d4) / d6);
    if (!acos5) continue;
    for (double theta5 : {*acos5, -*acos5}) {
      const double s5 = std::sin(theta5);
      double theta6;
      if (std::abs(s5) < 1e-10) {
        // Wrist singularity: joints 4 and 6 align; keep the seed's joint 6.
        theta6 = signs_[5] * seed_configuration[model_->joints()[chain_[5]].variable] + offsets_[5];
      } else {
        theta6 = std::atan2((-mi(1, 0) * s1 + mi(1, 1) * c1) / s5, (mi(0, 0) * s1 - mi(0, 1) * c1) / s5);
      }
      const Eigen::Isometry3d T14 = dh_transform(theta1, d1, 0, kPi / 2).inverse() * T * dh_transform(theta6, d6, 0, 0).inverse() *
                                    dh_transform(theta5, d5, 0, -kPi / 2).inverse();
      // Joints 2 and 3 form a planar 2R arm in frame 1's x-y plane reaching frame 4's origin.
      const Eigen::Vector3d p14 = T14.translation();
      const double reach2 = p14.x() * p14.x() + p14.y() * p14.y();
      const auto acos3 = safe_acos((reach2 - a2 * a2 - a3 * a3) / (2 * a2 * a3));
      if (!acos3) continue;
      for (double theta3 : {*acos3, -*acos3}) {
        const double theta2 =
            std::atan2(p14.y(), p14.x()) - std::atan2(a3 * std::sin(theta3), a2 + a3 * std::cos(theta3));
        const Eigen::Isometry3d T34 = dh_transform(theta3, 0, a3, 0).inverse() * dh_transform(theta2, 0, a2, 0).inverse() * T14;
        const double theta4 = std::atan2(T34(1, 0), T34(0, 0));
        const double angles[6] = {theta1, theta2, theta3, theta4, theta5, theta6};
        Eigen::VectorXd q = seed_configuration;
        bool ok = true;
        for (int i = 0; i < 6 && ok; ++i) {
          const Joint& joint = model_->joints()[chain_[i]];
          const auto value = fit_limits(wrap(signs_[i] * (angles[i] - offsets_[i])), joint, seed_configuration[joint.variable]);
          if (value) q[joint.variable] = *value; else ok = false;
        }
        if (ok && !contains_close(*model_, solutions, q, 1e-9)) solutions.push_back(q);
      }
    }
  }
  return solutions;
}

// ---------------------------------------------------------------------------------
// Numeric IK.

NumericIk::NumericIk(std::shared_ptr<const RobotModel> model, LinkIndex base, LinkIndex tip, Options options)
    : IkSolver(std::move(model), base, tip), options_(options) {}

bool NumericIk::descend(const Eigen::Isometry3d& goal, Eigen::VectorXd& q) const {
  const auto& joints = model_->joints();
  const Eigen::Index n = static_cast<Eigen::Index>(chain_.size());
  Eigen::Matrix<double, 6, Eigen::Dynamic> J(6, n);
  std::vector<Eigen::Isometry3d> frames(chain_.size());

  // Tip pose and the frames of the chain's joints (after origin, before motion).
  auto evaluate = [&](const Eigen::VectorXd& config, Eigen::Isometry3d& tip) {
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    std::size_t k = 0;
    for (JointIndex j : path_) {
      const Joint& joint = joints[j];
      if (joint.type != JointType::fixed) frames[k++] = t * joint.parent_T_joint;
      t = t * RobotModel::joint_transform(joint, joint.variable >= 0 ? config[joint.variable] : 0.0);
    }
    tip = t;
  };
  auto error_of = [&](const Eigen::Isometry3d& tip) {
    Eigen::Matrix<double, 6, 1> e;
    e.head<3>() = goal.translation() - tip.translation();
    const Eigen::AngleAxisd aa(goal.linear() * tip.linear().transpose());
    e.tail<3>() = aa.axis() * aa.angle();
    return e;
  };

  Eigen::Isometry3d tip;
  evaluate(q, tip);
  Eigen::Matrix<double, 6, 1> e = error_of(tip);
  double lambda = 1e-2;
  for (int iteration = 0; iteration < options_.max_iterations; ++iteration) {
    if (e.head<3>().norm() < options_.position_tolerance && e.tail<3>().norm() < options_.orientation_tolerance) return true;
    for (Eigen::Index k = 0; k < n; ++k) {
      const Joint& joint = joints[chain_[k]];
      const Eigen::Vector3d axis = frames[k].linear() * joint.axis;
      if (joint.type == JointType::revolute) {
        J.col(k) << axis.cross(tip.translation() - frames[k].translation()), axis;
      } else {
        J.col(k) << axis, Eigen::Vector3d::Zero();
      }
    }
    const Eigen::Matrix<double, 6, 6> A = J * J.transpose() + lambda * lambda * Eigen::Matrix<double, 6, 6>::Identity();
    const Eigen::VectorXd step = J.transpose() * A.ldlt().solve(e);
    Eigen::VectorXd candidate = q;
    for (Eigen::Index k = 0; k < n; ++k) {
      const Joint& joint = joints[chain_[k]];
      double value = q[joint.variable] + step[k];
      if (joint.continuous) value = wrap(value);
      candidate[joint.variable] = std::clamp(value, joint.lower, joint.upper);
    }
    Eigen::Isometry3d candidate_tip;
    evaluate(candidate, candidate_tip);
    const Eigen::Matrix<double, 6, 1> candidate_error = error_of(candidate_tip);
    if (candidate_error.squaredNorm() < e.squaredNorm()) {
      q = candidate;
      tip = candidate_tip;
      e = candidate_error;
      lambda = std::max(lambda * 0.3, 1e-9);
    } else {
      lambda = std::min(lambda * 5.0, 1e3);
      if (lambda >= 1e3) break;  // stuck in a local minimum or at a limit
      evaluate(q, tip);          // restore the frames of the accepted configuration
    }
  }
  return e.head<3>().norm() < options_.position_tolerance && e.tail<3>().norm() < options_.orientation_tolerance;
}

std::vector<Eigen::VectorXd> NumericIk::solve(const Eigen::Isometry3d& base_T_tip,
                                              const Eigen::VectorXd& seed_configuration,
                                              std::uint64_t random_seed) const {
  check_seed(*model_, seed_configuration);
  std::vector<Eigen::VectorXd> solutions;
  std::mt19937_64 rng(random_seed);
  for (int attempt = 0; attempt <= options_.restarts && solutions.size() < options_.max_solutions; ++attempt) {
    Eigen::VectorXd q = seed_configuration;
    for (JointIndex j : chain_) {
      const Joint& joint = model_->joints()[j];
      double& value = q[joint.variable];
      if (attempt == 0) {
        value = std::clamp(joint.continuous ? wrap(value) : value, joint.lower, joint.upper);
      } else {
        value = std::uniform_real_distribution<double>(joint.lower, joint.upper)(rng);
      }
    }
    if (descend(base_T_tip, q) && !contains_close(*model_, solutions, q, options_.distinct_tolerance)) {
      solutions.push_back(q);
    }
  }
  sort_by_seed(*model_, seed_configuration, solutions);
  return solutions;
}

}  // namespace cluttertamp::robot

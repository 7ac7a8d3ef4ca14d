#pragma once
// The integration points' part of an iteration: the temperatures and E, ν, α at the points,
// what the scheme keeps fixed at each point during a step (begin_step), and the point update
// with the internal forces (update), which returns what it found instead of leaving flags.
#include <span>
#include <vector>

#include "core/log.hpp"
#include "solve/model.hpp"
#include "solve/schemes.hpp"
#include "solve/state.hpp"

namespace hencky {

/// What one point pass found, the same on every rank.
struct PointPassResult {
  bool tangent_changed = false;   ///< a plastic point's matrix differs from the last pass's
  int undefined_cell = -1;        ///< a cell whose scheme needed F above the curve, or -1
  int negative_secant_cell = -1;  ///< a cell with a negative variable-stiffness secant, or -1
  int inverted_cell = -1;  ///< geometry: updated, a cell turned inside out by the iterate, or -1
  double delta_sigma = 0;         ///< the scheme's Δ^σ (0 without plasticity)
  double delta_eps = 0;           ///< the scheme's Δ^ε
  int plastic_points = 0;         ///< points that flow plastically in this iterate
  int holds_broken = 0;  ///< held points whose iterate lies on the other side of the yield stress
  /// The largest σ̃/σ̃_y − 1 over the points of plastic materials (Scheme::yield_stress; −inf
  /// without plasticity), and the points above σ̃_y·(1 + YieldExcess::slack).
  double yield_excess = -INFINITY;
  int points_above = 0;
};

/// How a point pass evaluates the points of plastic materials.
enum class PointMode {
  law,      ///< the scheme's point law: an iterate
  elastic,  ///< the elastic law and matrix, the scheme's memory set back (hencky's elastic start)
  initial,  ///< the scheme's initial parameters, its memory unchanged (the report's first solve,
            ///< Scheme::evaluate_initial)
};

class PointPass {
 public:
  /// `only`: this rank's cells (nullptr: every cell).
  PointPass(const Model& m, const std::vector<char>* only, const Scheme& scheme);

  /// The points' temperatures and E, ν, α at s.time from s.nodal_temperature. Throws an
  /// InputError when a thermal strain leaves the range of floating point; warns (once per
  /// material) about temperatures outside its tables. Collective.
  void temperatures(State& s, Log& log) const;
  /// Per plastic point, what stays fixed during the step to `trial` (flow direction, start
  /// slope, the curve at t+Δt) and the scheme's initial parameters.
  void begin_step(const State& c, const State& trial);
  /// Under `geometry: updated`, the configuration x of the step's start: the points' volume
  /// ratios J(t) = dv/dV there (start_volume_ratio).
  void set_configuration(const std::vector<Vec3>& x);
  /// This rank's cells (nullptr: every cell).
  const std::vector<char>* cells() const { return only_; }
  /// J(t) per point under `updated` (empty otherwise).
  const std::vector<double>& start_volume_ratio() const { return start_volume_ratio_; }
  /// The stress the point law starts the step from: σ(t), or the Kirchhoff stress J(t)σ(t)
  /// under `updated`.
  Voigt start_stress(const State& c, int p) const;
  /// The volume weight dv = det J·w of every point of this rank's cells on the configuration x,
  /// into v.
  static void point_volumes(const Model& m, const std::vector<Vec3>& x, std::vector<double>& v);
  /// Stresses, plastic state and internal forces of the iterate trial.u (elastic points:
  /// σ = σ(t) + D(t+Δt)(Δε − Δε^th), (1.9), (1.12); plastic ones: the scheme's point law),
  /// the scheme's matrices for the next solve, and the measures. Collective.
  /// `mode`: the point law (an iterate), or at a step's start the elastic law with the elastic
  /// matrix and the scheme's memory set back (the elastic start), or the scheme's initial
  /// parameters (the report's first solve).
  /// `x`: the nodes' coordinates the step is written on (the mesh's, or X + u(t) under
  /// `geometry: updated`, where the step is the updated Lagrangian one of CellDeformation).
  PointPassResult update(const State& c, State& trial, const std::vector<Vec3>& x,
                         PointMode mode = PointMode::law);
  /// The internal forces ∫Bᵀσ of the stresses of s over the configuration x, into f (whole on
  /// every rank). Collective.
  void internal_forces(const State& s, const std::vector<Vec3>& x, std::vector<double>& f) const;
  /// The scheme's matrix at each point, from the last update (plastic materials only).
  const std::vector<Tangent>& tangents() const { return tangent_; }
  /// Puts the matrices of an earlier pass back (a restart, EquilibriumMemory::tangents).
  void set_tangents(std::vector<Tangent> t) { tangent_ = std::move(t); }
  /// The initial-strain schemes' iterated state: Δε^0 (6 Voigt components, engineering
  /// shears) at this rank's points of plastic materials (PointIteration::e0, in the order of
  /// the cells).
  void initial_strains(std::vector<double>& e0) const;
  /// The weights of the same components, in the same order, in Anderson's least squares:
  /// volume times 2G (normal) or G (shear), so that the weighted square of a change of the
  /// deviatoric Δε^0 is an energy.
  void plastic_point_weights(std::vector<double>& weight) const;
  /// Replaces Δε^0 at those points (Anderson's mixed iterate).
  void set_initial_strains(std::span<const double> e0);
  /// Keeps, and puts back, the scheme's memory and matrix at every point (Anderson's fallback to
  /// the plain iterate; a line search's trial iterate). With the matrices put back, the next
  /// update's tangent_changed compares with the matrices of the iterate before the trial.
  void save_memory() {
    saved_iter_ = point_iter_;
    saved_tangent_ = tangent_;
  }
  void restore_memory() {
    point_iter_ = saved_iter_;
    tangent_ = saved_tangent_;
  }
  /// The initial-strain schemes' active set: every point of a plastic material with elastic
  /// unloading keeps, from now on in this step, the status (plastic or elastic) of its last
  /// iterate (PointIteration::held; begin_step frees them). Returns the number held plastic,
  /// over all ranks. Collective.
  int hold_plastic_set();
  /// The held points whose last iterate broke their hold change sides; the others stay.
  void move_broken_holds();
  /// Every point free again.
  void free_plastic_set();
  /// The largest yield excess of the last pass with its point's place (node, position), the
  /// same on every rank. Collective.
  YieldExcess largest_excess() const;
  /// The largest von Mises stress at the points of this model (every material) in `s`, with
  /// its point's place, the same on every rank. Collective.
  PointLargest largest_von_mises(const State& s) const;
  /// Warnings about the curves after a converged step: temperatures outside their tables,
  /// plastic strains beyond their last point. Collective.
  void check_curves(const State& s, Log& log) const;

 private:
  /// Δ^σ and Δ^ε of the report into r, made global.
  void measures(const State& trial, PointPassResult& r) const;
  bool mine(int e) const { return !only_ || (*only_)[e]; }
  LawState law_state(const State& c, State& trial, int p) const;
  void keep_plastic_state(const State& c, State& trial, int p);
  void take_plastic_update(const State& c, State& trial, int p, const PointUpdate& u);
  PointUpdate scheme_update(const State& c, State& trial, int p, const Voigt& sigma0,
                            const Voigt& d_eps, PointMode mode);
  /// σ̃/σ̃_y − 1 of point p at the iterate, from the law's stress (τ under `updated`).
  void measure_excess(const MaterialModel& mat, const State& c, State& trial, int p,
                      const Voigt& law_stress);
  void rotate_law_state(const PointLaw& law, const Mat3& r, State& trial, int p) const;
  /// f(p) for every point of this rank's cells of plastic materials, in the order of the cells.
  template <class F>
  void for_plastic_points(F&& f) const;

  const Model& m_;
  const std::vector<char>* only_;
  bool plastic_;
  const Scheme& scheme_;
  std::vector<PointStep> point_step_;
  std::vector<PointIteration> point_iter_, saved_iter_;
  std::vector<Tangent> tangent_;  ///< per point: the scheme's matrix of the last update
  std::vector<Tangent> saved_tangent_;
  /// point_volume_: the points' volume weights on the mesh (plastic materials or `updated`).
  std::vector<double> defect_sigma_, defect_eps_, point_volume_;
  std::vector<double> excess_;  ///< per point of a plastic material: σ̃/σ̃_y − 1 of the last pass
  std::vector<double> start_volume_ratio_;  ///< under `updated`: J(t) = dv/dV at the step's start
};

template <class F>
void PointPass::for_plastic_points(F&& f) const {
  for (int e = 0; e < m_.mesh().cells.size(); ++e) {
    if (!m_.material_of(e).plastic() || !mine(e)) continue;
    for (int p = m_.point_offset(e); p < m_.point_offset(e + 1); ++p) f(p);
  }
}

}  // namespace hencky

// Coarse-to-fine transfers of the OT solver: the density restricted to a grid half as fine, a coarse
// potential prolonged to the fine grid, and a folded prolonged potential smoothed until its map unfolds. The
// grid and its potential are those of Nader & Guennebaud 2018, "Instant transport maps on 2D grids", ACM TOG
// 37(6).
#pragma once

#include <functional>
#include <span>
#include <vector>

namespace iblx {

// 2x2 box restriction of an n x n density (n even) to n/2 x n/2: keeps the mean, and so the total mass,
// exactly.
std::vector<double> otRestrictDensity(std::span<const double> rho, int n);

// Coarse psi (m x m) to the fine grid (2m x 2m), mean 0: psi averaged over the four cells around each coarse
// vertex, then interpolated bilinearly between the coarse vertices at the fine cell centres. The average
// removes the checkerboard (-1)^(i+j), which the 2x2 gradient stencil does not see at interior vertices, so
// a converged coarse psi can carry any amount of it; interpolated directly from the cell centres it becomes
// steep fine gradients that fold the fine quads. Averaging keeps x^2/2 + psi convex where it was (a mean of
// convex functions), so the prolonged map stays monotone away from the coarse map's twisted quads. psi is a
// function on the unit square, so no rescaling.
std::vector<double> otProlongPotential(std::span<const double> psi, int m);

// psi (n x n) smoothed by `passes` binomial passes [1 2 1] / 4 along rows and then columns, with the
// reflecting boundary of the gradient stencil. Each pass's matrix is doubly stochastic, so the mean of psi
// is kept. A pass damps a wavelength of k cells by cos^2(pi / k) per axis: the two-cell twists of a
// prolonged map go, the transport at the scale of the coarse grid stays.
void otSmoothPotential(std::span<double> psi, int n, int passes);

// Smooths a folded psi by 1, 1, 2, 4, ... more passes (1, 2, 4, 8, ... in all) until foldedQuads(psi) is 0
// or the next batch would pass maxPasses. Sets `passes` to the passes made; returns the quads still folded
// (0 once unfolded; at least one when no pass was allowed).
int otSmoothUntilUnfolded(std::span<double> psi, int n, int maxPasses,
                          const std::function<int(std::span<const double>)>& foldedQuads, int& passes);

}  // namespace iblx

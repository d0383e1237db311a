// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraErrorModel.cxx
 * @brief The reconstruction's error estimate: the corner models against the
 * interpolant, calibrated by probe residuals.
 */
#include "penumbraReconstructionInternals.h"
#include "penumbraErrorModel.h"
#include "penumbraPointLocation.h"
#include "penumbraScene.h" // InputError

#include <algorithm>
#include <cmath>
#include <string>

namespace penumbra
{

using detail::CheckErrorOptions;
using detail::CheckTriangle;
using detail::ClampBarycentric;
using detail::Net;

//------------------------------------------------------------------------------
void detail::CheckErrorOptions(const ErrorEstimateOptions& o)
{
  if (!(o.ModelSafetyFactor >= 0.0 && o.ModelSafetyFactor <= 1e6))
  {
    throw InputError("Reconstruction: ModelSafetyFactor must be in [0, 1e6]");
  }
  if (!(o.ProbeSafetyFactor >= 0.0 && o.ProbeSafetyFactor <= 1e6))
  {
    throw InputError("Reconstruction: ProbeSafetyFactor must be in [0, 1e6]");
  }
  if (o.ModelLevel < 1 || o.ModelLevel > 64)
  {
    throw InputError("Reconstruction: ModelLevel must be in [1, 64]");
  }
}

//------------------------------------------------------------------------------
void Reconstruction::Internals::ModelError(
  int t, const double bIn[3], const double* interpolated, double* error) const
{
  double b[3];
  ClampBarycentric(bIn, b);
  const int* tri = this->T(t);
  const double* p[3] = { this->P(tri[0]), this->P(tri[1]), this->P(tri[2]) };
  const double u = b[0] * p[0][0] + b[1] * p[1][0] + b[2] * p[2][0];
  const double v = b[0] * p[0][1] + b[1] * p[1][1] + b[2] * p[2][1];
  for (int c = 0; c < this->NC; ++c)
  {
    error[c] = 0.0;
  }
  for (int i = 0; i < 3; ++i)
  {
    const double du = u - p[i][0];
    const double dv = v - p[i][1];
    const std::size_t s = this->CornerSector[3 * t + i];
    for (int c = 0; c < this->NC; ++c)
    {
      const double* q = this->SectorModel.data() + (s * this->NC + c) * 9;
      const double model = this->Value(tri[i], c) + q[0] * du + q[1] * dv +
        0.5 * q[2] * du * du + q[3] * du * dv + 0.5 * q[4] * dv * dv +
        q[5] * du * du * du / 6.0 + 0.5 * q[6] * du * du * dv + 0.5 * q[7] * du * dv * dv +
        q[8] * dv * dv * dv / 6.0;
      error[c] = std::max(error[c], std::abs(model - interpolated[c]));
    }
  }
}

//------------------------------------------------------------------------------
// Per triangle and channel (both empty without probes): bound =
// ProbeSafetyFactor * max |residual|, modelScale = the factor k_t of
// ErrorEstimateOptions (1 for a triangle without probes).
void Reconstruction::Internals::CalibrateWithProbes(const ErrorProbes* probes,
  const ErrorEstimateOptions& options, std::vector<double>& bound,
  std::vector<double>& modelScale) const
{
  bound.clear();
  modelScale.clear();
  if (!probes)
  {
    return;
  }
  const int nt = this->Mesh.GetNumberOfTriangles();
  const int nc = this->NC;
  if (probes->Residuals.size() != probes->Triangles.size() * static_cast<std::size_t>(nc))
  {
    throw InputError("Reconstruction: ErrorProbes has " + std::to_string(probes->Residuals.size()) +
      " residuals for " + std::to_string(probes->Triangles.size()) + " probes of " +
      std::to_string(nc) + " channels");
  }
  std::vector<double> measured(static_cast<std::size_t>(nt) * nc, 0.0);
  std::vector<char> probed(nt, 0);
  for (std::size_t i = 0; i < probes->Triangles.size(); ++i)
  {
    const int t = probes->Triangles[i];
    if (t < 0 || t >= nt)
    {
      throw InputError("Reconstruction: probe " + std::to_string(i) + " has triangle id " +
        std::to_string(t) + " out of range [0, " + std::to_string(nt) + ")");
    }
    probed[t] = 1;
    for (int c = 0; c < nc; ++c)
    {
      const double r = probes->Residuals[i * nc + c];
      if (!std::isfinite(r))
      {
        throw InputError(
          "Reconstruction: probe " + std::to_string(i) + " has a non-finite residual");
      }
      double& m = measured[static_cast<std::size_t>(t) * nc + c];
      m = std::max(m, std::abs(r));
    }
  }
  bound.resize(measured.size());
  modelScale.assign(measured.size(), 1.0);
  std::vector<double> value(nc), error(nc), claimed(nc);
  const double midpoints[3][3] = { { 0.5, 0.5, 0.0 }, { 0.0, 0.5, 0.5 }, { 0.5, 0.0, 0.5 } };
  for (int t = 0; t < nt; ++t)
  {
    const std::size_t at = static_cast<std::size_t>(t) * nc;
    std::fill(claimed.begin(), claimed.end(), 0.0);
    if (probed[t])
    {
      for (const auto& b : midpoints)
      {
        this->Evaluate(t, b, value.data(), nullptr);
        this->ModelError(t, b, value.data(), error.data());
        for (int c = 0; c < nc; ++c)
        {
          claimed[c] = std::max(claimed[c], error[c]);
        }
      }
    }
    for (int c = 0; c < nc; ++c)
    {
      bound[at + c] = options.ProbeSafetyFactor * measured[at + c];
      if (claimed[c] > measured[at + c])
      {
        modelScale[at + c] = measured[at + c] / claimed[c];
      }
    }
  }
}

//------------------------------------------------------------------------------
void Reconstruction::EstimateErrors(int count, const int* triangles, const double* barycentrics,
  const ErrorProbes* probes, const ErrorEstimateOptions& options, double* errors) const
{
  const Internals& in = *this->Internal;
  CheckErrorOptions(options);
  const int nt = in.Mesh.GetNumberOfTriangles();
  for (int i = 0; i < count; ++i)
  {
    CheckTriangle(triangles[i], nt);
  }
  std::vector<double> probeBounds, modelScale;
  in.CalibrateWithProbes(probes, options, probeBounds, modelScale);
  const int nc = in.NC;
  std::vector<double> value(nc);
  for (int i = 0; i < count; ++i)
  {
    const int t = triangles[i];
    double* error = errors + static_cast<std::size_t>(i) * nc;
    in.Evaluate(t, barycentrics + 3 * i, value.data(), nullptr);
    in.ModelError(t, barycentrics + 3 * i, value.data(), error);
    for (int c = 0; c < nc; ++c)
    {
      const std::size_t at = static_cast<std::size_t>(t) * nc + c;
      error[c] *= options.ModelSafetyFactor * (modelScale.empty() ? 1.0 : modelScale[at]);
      if (!probeBounds.empty())
      {
        error[c] = std::max(error[c], probeBounds[at]);
      }
    }
  }
}

void Reconstruction::ComputeTriangleErrorBounds(const ErrorProbes* probes,
  const ErrorEstimateOptions& options, std::vector<double>& bounds) const
{
  const Internals& in = *this->Internal;
  CheckErrorOptions(options);
  const int nt = in.Mesh.GetNumberOfTriangles();
  const int nc = in.NC;
  std::vector<double> probeBounds, modelScale;
  in.CalibrateWithProbes(probes, options, probeBounds, modelScale); // validates first
  bounds.assign(static_cast<std::size_t>(nt) * nc, 0.0);
  const int level = options.ModelLevel;
  const bool cubic = in.Options.Mode == ReconstructionMode::CloughTocher;
  std::vector<Net> nets(nc);
  std::vector<double> value(nc), error(nc);
  for (int t = 0; t < nt; ++t)
  {
    if (cubic)
    {
      for (int c = 0; c < nc; ++c)
      {
        in.ComputeNet(t, c, nets[c]);
      }
    }
    double* out = bounds.data() + static_cast<std::size_t>(t) * nc;
    for (int a = 0; a <= level; ++a)
    {
      for (int b = 0; a + b <= level; ++b)
      {
        const double bary[3] = { static_cast<double>(level - a - b) / level,
          static_cast<double>(a) / level, static_cast<double>(b) / level };
        in.EvaluateWithNets(t, cubic ? nets.data() : nullptr, bary, value.data(), nullptr);
        in.ModelError(t, bary, value.data(), error.data());
        for (int c = 0; c < nc; ++c)
        {
          const double scale =
            modelScale.empty() ? 1.0 : modelScale[static_cast<std::size_t>(t) * nc + c];
          out[c] = std::max(out[c], options.ModelSafetyFactor * scale * error[c]);
        }
      }
    }
    if (!probeBounds.empty())
    {
      for (int c = 0; c < nc; ++c)
      {
        out[c] = std::max(out[c], probeBounds[static_cast<std::size_t>(t) * nc + c]);
      }
    }
  }
}

} // namespace penumbra

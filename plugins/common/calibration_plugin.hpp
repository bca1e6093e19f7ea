// What the calibration targets of this project's plugins (duncan_chang, goodman_nonlinear,
// hyperbolic_interface) share: a Calibration that is one fitting function of the curves of one
// kind of laboratory test.
#pragma once

#include "stratum/calibration.hpp"

#include <memory>
#include <utility>

namespace stratum::calibration_plugin {

/// The Calibration whose fit() is fit(curves), for curves of the laboratory test `test`.
template <class Fit> class FitCalibration final : public Calibration {
public:
  FitCalibration(LabTest test, Fit fit) : test_(test), fit_(std::move(fit)) {}
  [[nodiscard]] LabTest lab_test() const override { return test_; }
  [[nodiscard]] FittedParameters fit(const LabCurves& curves) const override { return fit_(curves); }

private:
  LabTest test_;
  Fit fit_;
};

/// A FitCalibration, as Factory<Calibration>::create returns it.
template <class Fit> [[nodiscard]] std::unique_ptr<Calibration> fitting(LabTest test, Fit fit) {
  return std::make_unique<FitCalibration<Fit>>(test, std::move(fit));
}

} // namespace stratum::calibration_plugin

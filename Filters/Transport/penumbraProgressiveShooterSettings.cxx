// SPDX-License-Identifier: GPL-3.0-or-later
// The validation of ProgressiveShooterSettings (declared in
// penumbraProgressiveShooter.h), against the ranges documented there.
#include "penumbraProgressiveShooter.h"

#include <string>

namespace penumbra
{

void ProgressiveShooterSettings::Validate() const
{
  const auto fail = [](const std::string& what) {
    throw InputError("progressive shooter: " + what);
  };
  if (!(this->UnshotFraction >= 0.0 && this->UnshotFraction <= 1.0))
  {
    fail("UnshotFraction must be in [0, 1], got " + std::to_string(this->UnshotFraction));
  }
  if (this->MaximumShots < 0)
  {
    fail("MaximumShots must be >= 0, got " + std::to_string(this->MaximumShots));
  }
  if (!(this->ExactPowerFraction >= 0.0))
  {
    fail("ExactPowerFraction must be in [0, inf], got " + std::to_string(this->ExactPowerFraction));
  }
  if (!(this->CoarseShotFraction >= 0.0 && this->CoarseShotFraction <= 1.0))
  {
    fail("CoarseShotFraction must be in [0, 1], got " + std::to_string(this->CoarseShotFraction));
  }
  if (!(this->OpeningAngle > 0.0 && this->OpeningAngle <= 2.0))
  {
    fail("OpeningAngle must be in (0, 2], got " + std::to_string(this->OpeningAngle));
  }
  if (!(this->ReceiverClusterSize >= 0 && this->ReceiverClusterSize <= 4096))
  {
    fail("ReceiverClusterSize must be in [0, 4096], got " +
      std::to_string(this->ReceiverClusterSize));
  }
  if (!(this->LeafSize > 0.0 && this->LeafSize <= 1.0))
  {
    fail("LeafSize must be in (0, 1], got " + std::to_string(this->LeafSize));
  }
  if (!(this->BoundaryOffset >= 0.0 && this->BoundaryOffset <= 1e-2))
  {
    fail("BoundaryOffset must be in [0, 1e-2], got " + std::to_string(this->BoundaryOffset));
  }
  if (!(this->RayOriginOffset >= 0.0 && this->RayOriginOffset <= 1e-2))
  {
    fail("RayOriginOffset must be in [0, 1e-2], got " + std::to_string(this->RayOriginOffset));
  }
}

} // namespace penumbra

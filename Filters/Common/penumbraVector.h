// SPDX-License-Identifier: GPL-3.0-or-later
/**
 * @file penumbraVector.h
 * @brief Small value types shared by the Penumbra core: 3D vectors and RGB triples.
 *
 * Plain C++ with no VTK or third-party types, so that every algorithm of the
 * core can be unit-tested directly and the types can cross module boundaries.
 */
#ifndef penumbraVector_h
#define penumbraVector_h

#include <cmath>

namespace penumbra
{

/// A point or direction in 3D, in scene units.
struct Vec3
{
  double X = 0.0;
  double Y = 0.0;
  double Z = 0.0;

  constexpr Vec3() = default;
  constexpr Vec3(double x, double y, double z)
    : X(x)
    , Y(y)
    , Z(z)
  {
  }

  double operator[](int i) const { return i == 0 ? X : (i == 1 ? Y : Z); }
  double& operator[](int i) { return i == 0 ? X : (i == 1 ? Y : Z); }
  Vec3& operator+=(const Vec3& o)
  {
    X += o.X;
    Y += o.Y;
    Z += o.Z;
    return *this;
  }
  Vec3& operator-=(const Vec3& o)
  {
    X -= o.X;
    Y -= o.Y;
    Z -= o.Z;
    return *this;
  }
  Vec3& operator*=(double s)
  {
    X *= s;
    Y *= s;
    Z *= s;
    return *this;
  }
};

inline Vec3 operator+(Vec3 a, const Vec3& b)
{
  return a += b;
}
inline Vec3 operator-(Vec3 a, const Vec3& b)
{
  return a -= b;
}
inline Vec3 operator-(const Vec3& a)
{
  return { -a.X, -a.Y, -a.Z };
}
inline Vec3 operator*(Vec3 a, double s)
{
  return a *= s;
}
inline Vec3 operator*(double s, Vec3 a)
{
  return a *= s;
}
inline Vec3 operator/(const Vec3& a, double s)
{
  return { a.X / s, a.Y / s, a.Z / s };
}
inline double Dot(const Vec3& a, const Vec3& b)
{
  return a.X * b.X + a.Y * b.Y + a.Z * b.Z;
}
inline Vec3 Cross(const Vec3& a, const Vec3& b)
{
  return { a.Y * b.Z - a.Z * b.Y, a.Z * b.X - a.X * b.Z, a.X * b.Y - a.Y * b.X };
}
inline double SquaredLength(const Vec3& a)
{
  return Dot(a, a);
}
inline double Length(const Vec3& a)
{
  return std::sqrt(Dot(a, a));
}
inline Vec3 Normalized(const Vec3& a)
{
  const double len = Length(a);
  return len > 0.0 ? a / len : Vec3();
}
inline bool IsFinite(const Vec3& a)
{
  return std::isfinite(a.X) && std::isfinite(a.Y) && std::isfinite(a.Z);
}

/// An RGB triple (reflectance, radiance, ...). Channels are independent.
struct RGB
{
  double R = 0.0;
  double G = 0.0;
  double B = 0.0;

  constexpr RGB() = default;
  constexpr RGB(double r, double g, double b)
    : R(r)
    , G(g)
    , B(b)
  {
  }

  double operator[](int i) const { return i == 0 ? R : (i == 1 ? G : B); }
  double& operator[](int i) { return i == 0 ? R : (i == 1 ? G : B); }
  RGB& operator+=(const RGB& o)
  {
    R += o.R;
    G += o.G;
    B += o.B;
    return *this;
  }
  RGB& operator*=(double s)
  {
    R *= s;
    G *= s;
    B *= s;
    return *this;
  }
  /// Mean of the three channels: the scalar Penumbra uses to rank power.
  double Mean() const { return (R + G + B) / 3.0; }
  bool IsZero() const { return R == 0.0 && G == 0.0 && B == 0.0; }
};

inline RGB operator+(RGB a, const RGB& b)
{
  return a += b;
}
inline RGB operator*(RGB a, double s)
{
  return a *= s;
}
inline RGB operator*(double s, RGB a)
{
  return a *= s;
}
/// Channel-wise product (e.g. reflectance times irradiance).
inline RGB operator*(const RGB& a, const RGB& b)
{
  return { a.R * b.R, a.G * b.G, a.B * b.B };
}

} // namespace penumbra

#endif

#include "nestwalk/geometry/volumes.h"

#include <Eigen/LU>
#include <Eigen/SVD>

namespace nestwalk {

template <class T>
Mat3<T> orthonormalized(const Mat3<T>& m) {
  // In double even for float: a float SVD leaves errors above kAxesTolerance<float>, while rounding
  // a double rotation to float stays within it.
  Eigen::JacobiSVD<Mat3<double>> svd(m.template cast<double>(), Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat3<double> r = svd.matrixU() * svd.matrixV().transpose();
  if (r.determinant() < 0.0) {
    // A reflection: flip the direction of least weight so the result is a rotation.
    Mat3<double> u = svd.matrixU();
    u.col(2) = -u.col(2);
    r = u * svd.matrixV().transpose();
  }
  return r.cast<T>();
}

template Mat3<float> orthonormalized(const Mat3<float>&);
template Mat3<double> orthonormalized(const Mat3<double>&);

}  // namespace nestwalk

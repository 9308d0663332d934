#include "engine/geometry/volumes.h"

#include <Eigen/LU>
#include <Eigen/SVD>

namespace nestwalk {

template <class T>
Mat3<T> orthonormalized(const Mat3<T>& m) {
  Eigen::JacobiSVD<Mat3<T>> svd(m, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat3<T> r = svd.matrixU() * svd.matrixV().transpose();
  if (r.determinant() < T(0)) {
    // A reflection: flip the direction of least weight so the result is a rotation.
    Mat3<T> u = svd.matrixU();
    u.col(2) = -u.col(2);
    r = u * svd.matrixV().transpose();
  }
  return r;
}

template Mat3<float> orthonormalized(const Mat3<float>&);
template Mat3<double> orthonormalized(const Mat3<double>&);

}  // namespace nestwalk

// The chessboard scene: a printed calibration target (kChessboardCols x
// kChessboardRows inner corners, kChessboardSquare squares, black on white
// with a white margin) on the plane z = 0, framed from 50 cm: the board of
// 27 x 21 cm spans ~270 x 210 px of the 640 x 480 rig, in both cameras,
// whatever the calibration trajectory's tilt. For the calibration tests
// (cameracalibrator.py's StereoCalibrator on rendered views).
#include <cmath>

#include "hapi_sim/scene.hpp"

namespace hapi_sim {
namespace {

constexpr float kWhite = 200.0f, kBlack = 30.0f;  // grey levels at unit gain

class ChessboardScene : public Scene {
 public:
  ChessboardScene() {
    SurfaceSpec board;
    board.type = SurfaceSpec::Plane;
    board.centre = Eigen::Vector3d::Zero();
    board.axis = Eigen::Vector3d::UnitZ();
    board.half_extent = 0.4;  // the white card around the squares
    surfaces_ = {board};
  }
  std::string name() const override { return "chessboard"; }
  const std::vector<SurfaceSpec>& surfaces() const override { return surfaces_; }
  ViewGeometry view() const override {
    ViewGeometry v;
    v.centre = Eigen::Vector3d::Zero();
    v.along = Eigen::Vector3d::UnitX();
    v.up = Eigen::Vector3d::UnitY();
    v.standoff = 0.50;
    v.extent = 0.04;
    return v;
  }
  bool trace(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double* t, float* grey) const override {
    if (!intersectSurface(surfaces_[0], o, d, t)) return false;
    const Eigen::Vector3d X = o + *t * d;
    // Squares: (cols + 1) x (rows + 1), centred on the origin.
    const double u = X.x() / kChessboardSquare + 0.5 * (kChessboardCols + 1);
    const double v = X.y() / kChessboardSquare + 0.5 * (kChessboardRows + 1);
    const bool on_board = u >= 0 && u < kChessboardCols + 1 && v >= 0 && v < kChessboardRows + 1;
    const bool black = on_board && ((static_cast<int>(std::floor(u)) + static_cast<int>(std::floor(v))) % 2 == 0);
    *grey = black ? kBlack : kWhite;
    return true;
  }
  std::string textureSource() const override { return "chessboard"; }

 private:
  std::vector<SurfaceSpec> surfaces_;
};

}  // namespace

std::unique_ptr<Scene> makeChessboardScene() { return std::make_unique<ChessboardScene>(); }

}  // namespace hapi_sim

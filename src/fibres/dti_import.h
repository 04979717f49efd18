#pragma once

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/point.h>
#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>
#include <deal.II/grid/tria.h>

#include "fibres/fibre_basis.h"

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

/// @file
/// The `dti` fibre generator: fibres from a diffusion-tensor image.
///
/// The image is a VTK XML image file (.vti, read with vtkXMLImageDataReader)
/// whose point data holds one diffusion tensor per voxel, either as 9
/// components (row-major xx, xy, xz, yx, yy, yz, zx, zy, zz; symmetrized,
/// an asymmetry above 1e-3 of the norm is an error) or as 6 components in
/// VTK's symmetric order xx, yy, zz, xy, yz, xz. The tensor components are
/// taken in the image's physical frame (the frame of its Origin, Spacing and
/// Direction). The tensor unit does not matter: only eigenvectors and the
/// fractional anisotropy are used. A voxel whose tensor is exactly zero is
/// background (no data); any other tensor must be symmetric positive
/// definite.
///
/// Interpolation is log-Euclidean (Arsigny et al. 2006, Magn. Reson. Med.
/// 56:411): log D is precomputed once per voxel, a query point X is mapped to
/// the continuous voxel index, the logs of the eight surrounding voxels are
/// averaged with trilinear weights, and the eigen-decomposition of the mean
/// log L gives the tensor exp(L) (same eigenvectors, eigenvalues exp(mu)).
/// The fibre f is the principal eigenvector, the sheet s the second one; both
/// are mapped to the mesh by the linear part A of the image-to-mesh transform
/// (f = A f_image / |A f_image|, s = A s_image orthogonalized against f) and
/// n = f x s.
///
/// Sign convention: eigenvectors have no sign. f is chosen with f . e_ref > 0
/// and s with s . e_ref > 0, where e_ref = e_z, ties (|v . e_z| < 1e-12)
/// broken by e_y, then e_x; n = f x s makes the frame right-handed. The
/// mechanics uses only f (x) f, s (x) s and squared fibre-sheet invariants
/// (Guccione E_fs^2, Holzapfel-Ogden I_8fs^2), so the sign changes no result.

namespace systole::Fibres
{
  /// Subsection "Fibres / DTI".
  struct DTIParameters
  {
    /// The .vti file, absolute (resolved against the parameter file's folder).
    std::string file;
    /// Name of the point-data array; empty: the tensor attribute of the
    /// point data.
    std::string tensor_array = "tensors";
    /// Row-major 3 x 4 matrix [A | b]: x_mesh = A x_image + b [mm].
    std::array<double, 12> image_to_mesh = {
      {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0}};
    /// Points with a smaller fractional anisotropy are rejected [-].
    double minimum_fractional_anisotropy = 0.05;
    /// The run stops when a larger fraction of the mesh points is rejected.
    double maximum_rejected_fraction = 0.05;

    /// Declares the entries in subsection "Fibres" / "DTI" (enters both).
    static void
    declare(dealii::ParameterHandler &prm);

    /// Reads the entries; a relative File is resolved against
    /// @p base_directory (the parameter file's folder). Checks that A is
    /// invertible; does not open the file (only the dti generator needs it).
    static DTIParameters
    parse(const dealii::ParameterHandler &prm,
          const std::string              &base_directory);
  };

  /// Relative eigenvalue gap (lambda_i - lambda_{i+1}) / lambda_1 below which
  /// the fibre (i = 1) or the sheet (i = 2) is not unique; such points count as
  /// low anisotropy.
  constexpr double dti_minimum_relative_eigenvalue_gap = 1e-3;

  /// Why a point got the frame it got.
  enum class DTIStatus
  {
    valid,          ///< interpolated in the image, anisotropic enough
    outside,        ///< outside the image extent, or mostly in background
    low_anisotropy, ///< FA below the minimum or eigenvalue gap too small
  };

  /// The result at one point.
  struct DTISample
  {
    FibreBasis basis; ///< the frame used (the fallback when not valid)
    DTIStatus  status                = DTIStatus::valid;
    double     fractional_anisotropy = 0.0; ///< of the interpolated tensor
  };

  /// Counts of points by status.
  struct DTIStatistics
  {
    std::uint64_t n_points         = 0;
    std::uint64_t n_outside        = 0;
    std::uint64_t n_low_anisotropy = 0;

    void
    add(const DTIStatus status);
    std::uint64_t
    n_rejected() const;
    /// n_rejected / n_points (0 without points).
    double
    rejected_fraction() const;
  };

  /// A diffusion-tensor image, read once, answering fibre frames at mesh
  /// points.
  ///
  /// Points outside the image (or whose trilinear stencil has less than half
  /// its weight on non-background voxels) count as outside; points with
  /// FA < Minimum fractional anisotropy or too small an eigenvalue gap count as
  /// low anisotropy. Both get the frame of the nearest valid voxel (nearest in
  /// 26-neighbour voxel steps from the voxel closest to the point, clamped to
  /// the image), so the field stays smooth near the edges of the data.
  class DTIField
  {
  public:
    /// Reads and checks the image, precomputes log D of every voxel. Throws
    /// ExcMessage naming the file when it is missing or unreadable, lacks the
    /// array, has a wrong component count, a tensor that is not symmetric
    /// positive definite, fewer than two voxels along an axis, or no valid
    /// voxel at all.
    explicit DTIField(const DTIParameters &params);

    /// The frame at the mesh point @p X [mm]; no side effects.
    DTISample
    sample(const dealii::Point<3> &X) const;

    /// The frame at @p X; counts the point in statistics().
    FibreBasis
    operator()(const dealii::Point<3> &X);

    /// Counts of the points passed to operator() so far.
    const DTIStatistics &
    statistics() const;

    /// The log-Euclidean interpolated tensor at @p X, in the image frame and
    /// the file's unit. Throws if @p X is outside (as defined above).
    dealii::SymmetricTensor<2, 3>
    tensor(const dealii::Point<3> &X) const;

    /// Number of voxels along each image axis.
    std::array<unsigned int, 3>
    n_voxels() const;

    /// Number of voxels that are valid (data, anisotropic, unique f and s).
    std::uint64_t
    n_valid_voxels() const;

    /// Lower and upper corners of the bounding box of the image, in mesh
    /// coordinates [mm].
    std::pair<dealii::Point<3>, dealii::Point<3>>
    mesh_bounding_box() const;

    const DTIParameters &
    parameters() const;

  private:
    /// Log-mean of the stencil of @p X; false when outside.
    bool
    log_mean(const dealii::Point<3> &X, std::array<double, 6> &L) const;
    /// Frame from a log tensor (image frame), with FA and status.
    DTISample
    frame_from_log(const std::array<double, 6> &L) const;
    /// Voxel index (flat) closest to @p X, clamped to the image.
    std::uint64_t
    closest_voxel(const dealii::Point<3> &X) const;

    DTIParameters               params;
    std::array<unsigned int, 3> n;
    /// Mesh point -> continuous voxel index (0 at the first voxel).
    dealii::Tensor<2, 3> index_matrix;
    dealii::Tensor<1, 3> index_offset;
    /// Linear part A of the image-to-mesh transform (image -> mesh vectors).
    dealii::Tensor<2, 3> A;
    /// log D per voxel (xx, yy, zz, xy, yz, xz); background voxels are flagged.
    std::vector<std::array<double, 6>> logs;
    std::vector<std::uint8_t>          background;
    /// Per voxel, the flat index of the nearest valid voxel.
    std::vector<std::uint64_t> nearest_valid;
    std::uint64_t              n_valid = 0;
    dealii::Point<3>           box_lower, box_upper;
    DTIStatistics              counts;
  };

  /// The `dti` generator on the mesh @p tria; returns a Fibres::FibreField
  /// (the type is spelled out so that fibre_field.h can include this header).
  /// Collective over the triangulation's communicator: it reads the image on
  /// every rank, samples the 2 x 2 x 2 Gauss points of every locally owned cell
  /// (straight-sided cell geometry), sums the counts over the ranks, passes a
  /// one-line summary to @p report (on every rank, the same text; pass a rank-0
  /// printer) and throws on every rank when the rejected fraction exceeds
  /// Maximum rejected fraction, naming the file, the fraction, the limit, the
  /// mesh and image bounding boxes and the fix. The returned field gives the
  /// validated frames of DTIField at the points it is asked for.
  std::function<
    void(const dealii::Triangulation<3, 3>::active_cell_iterator &cell,
         const std::vector<dealii::Point<3>>                     &points,
         std::vector<FibreBasis>                                 &bases)>
  create_dti_fibre_field(
    const DTIParameters                            &params,
    const dealii::Triangulation<3, 3>              &tria,
    const std::function<void(const std::string &)> &report = {});
} // namespace systole::Fibres

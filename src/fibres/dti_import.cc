#include "fibres/dti_import.h"

#include <deal.II/base/geometry_info.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/quadrature.h>
#include <deal.II/base/utilities.h>
#include <deal.II/grid/reference_cell.h>

#include "base/format.h"
#include "fibres/frames.h"
#include "geometry/mesh_file.h"
#include "geometry/point_location.h"
#include "geometry/vtk_messages.h"

#include <Eigen/Dense>
#include <vtkCallbackCommand.h>
#include <vtkCommand.h>
#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkSmartPointer.h>
#include <vtkXMLImageDataReader.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <filesystem>
#include <limits>
#include <memory>

namespace systole::Fibres
{
  namespace
  {
    using Matrix3 = Eigen::Matrix3d;

    void
    fail(const std::string &message)
    {
      AssertThrow(false, dealii::ExcMessage(message));
    }

    /// Significant digits of the numbers in messages.
    constexpr int digits = 4;

    /// Symmetric 3 x 3 matrix from (xx, yy, zz, xy, yz, xz).
    Matrix3
    to_matrix(const std::array<double, 6> &c)
    {
      Matrix3 m;
      m << c[0], c[3], c[5], c[3], c[1], c[4], c[5], c[4], c[2];
      return m;
    }

    std::array<double, 6>
    to_components(const Matrix3 &m)
    {
      return {{m(0, 0), m(1, 1), m(2, 2), m(0, 1), m(1, 2), m(0, 2)}};
    }

    /// FA of eigenvalues @p l (any positive scale).
    double
    fractional_anisotropy(const Eigen::Vector3d &l)
    {
      const double mean = l.mean();
      const double norm = l.norm();
      return norm > 0.0
               ? std::sqrt(1.5) * (l.array() - mean).matrix().norm() / norm
               : 0.0;
    }

    /// Whether eigenvalues @p l (ascending, positive) give a valid frame.
    bool
    is_anisotropic(const Eigen::Vector3d &l, const double minimum_fa)
    {
      const double gap = dti_minimum_relative_eigenvalue_gap * l[2];
      return fractional_anisotropy(l) >= minimum_fa && l[2] - l[1] >= gap &&
             l[1] - l[0] >= gap;
    }

    /// Deterministic sign: v . e_z > 0, ties broken by e_y, then e_x.
    void
    fix_sign(dealii::Tensor<1, 3> &v)
    {
      for (const unsigned int d : {2u, 1u, 0u})
        if (std::abs(v[d]) > 1e-12)
          {
            if (v[d] < 0.0)
              v *= -1.0;
            return;
          }
    }

  } // namespace

  // ---------------------------------------------------------------------------
  // Parameters

  void
  DTIParameters::declare(dealii::ParameterHandler &prm)
  {
    using namespace dealii::Patterns;
    prm.enter_subsection("Fibres");
    prm.enter_subsection("DTI");
    prm.declare_entry(
      "File",
      "",
      FileName(),
      "Diffusion-tensor image for Generator = dti: a VTK XML image file (.vti) "
      "with one tensor per voxel in its point data, 9 components (row-major) "
      "or 6 (xx, yy, zz, xy, yz, xz), in the image's physical frame; zero "
      "tensors mark background. A relative path is relative to the folder of "
      "this parameter file. Units: -.");
    prm.declare_entry("Tensor array name",
                      "tensors",
                      Anything(),
                      "Name of the point-data array holding the tensors; "
                      "empty: the point data's tensor attribute. Units: -.");
    prm.declare_entry(
      "Image to mesh transform",
      "1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0",
      List(Double(), 12, 12),
      "Affine map from the image's physical coordinates to the mesh, as the "
      "12 numbers of the 3 x 4 matrix [A | b] row by row: x_mesh = A x_image "
      "+ b. A must be invertible; fibre directions are mapped by A. Units: "
      "mm per image unit (A), mm (b).");
    prm.declare_entry(
      "Minimum fractional anisotropy",
      "0.05",
      Double(0, 1),
      "Mesh points where the interpolated tensor has a smaller fractional "
      "anisotropy (or two nearly equal eigenvalues) are rejected and take the "
      "frame of the nearest valid voxel. Myocardium: 0.2-0.5. Units: -.");
    prm.declare_entry(
      "Maximum rejected fraction",
      "0.05",
      Double(0, 1),
      "The run stops when a larger fraction of the mesh points falls outside "
      "the image or on rejected tensors. Units: -.");
    prm.leave_subsection();
    prm.leave_subsection();
  }

  DTIParameters
  DTIParameters::parse(const dealii::ParameterHandler &prm,
                       const std::string              &base_directory)
  {
    DTIParameters                  p;
    const std::vector<std::string> path = {"Fibres", "DTI"};
    p.file = Geometry::file_in_directory(prm.get(path, "File"), base_directory);
    p.tensor_array    = prm.get(path, "Tensor array name");
    const auto values = dealii::Utilities::string_to_double(
      dealii::Utilities::split_string_list(prm.get(path,
                                                   "Image to mesh transform"),
                                           ','));
    AssertThrow(values.size() == 12,
                dealii::ExcMessage(
                  "Fibres / DTI / Image to mesh transform needs 12 numbers."));
    std::copy(values.begin(), values.end(), p.image_to_mesh.begin());
    Matrix3 A;
    for (unsigned int i = 0; i < 3; ++i)
      for (unsigned int j = 0; j < 3; ++j)
        A(i, j) = p.image_to_mesh[4 * i + j];
    const double size = A.norm();
    AssertThrow(std::abs(A.determinant()) > 1e-12 * size * size * size,
                dealii::ExcMessage(
                  "Fibres / DTI / Image to mesh transform: its 3 x 3 part A "
                  "(numbers 1-3, 5-7, 9-11) is singular (det A = " +
                  format_number(A.determinant(), digits) +
                  "); give an invertible map, e.g. 1, 0, 0, 0, 0, 1, 0, 0, 0, "
                  "0, 1, 0 for the identity."));
    p.minimum_fractional_anisotropy =
      prm.get_double(path, "Minimum fractional anisotropy");
    p.maximum_rejected_fraction =
      prm.get_double(path, "Maximum rejected fraction");
    return p;
  }

  // ---------------------------------------------------------------------------
  // Statistics

  void
  DTIStatistics::add(const DTIStatus status)
  {
    ++n_points;
    if (status == DTIStatus::outside)
      ++n_outside;
    else if (status == DTIStatus::low_anisotropy)
      ++n_low_anisotropy;
  }

  std::uint64_t
  DTIStatistics::n_rejected() const
  {
    return n_outside + n_low_anisotropy;
  }

  double
  DTIStatistics::rejected_fraction() const
  {
    return n_points == 0 ? 0.0
                         : static_cast<double>(n_rejected()) /
                             static_cast<double>(n_points);
  }

  // ---------------------------------------------------------------------------
  // DTIField

  namespace
  {
    /// The reader of the image @p file, read; VTK's messages are collected
    /// into the exception text (@p where: the parameter that names it).
    vtkSmartPointer<vtkXMLImageDataReader>
    read_image(const std::string &file, const std::string &where)
    {
      AssertThrow(!file.empty(),
                  dealii::ExcMessage(where +
                                     " is empty: Generator = dti needs a "
                                     "diffusion-tensor image (.vti)."));
      AssertThrow(std::filesystem::is_regular_file(file),
                  dealii::ExcMessage(
                    where + ": cannot open '" + file +
                    "' (no such file). A relative path is taken from the "
                    "folder of the parameter file."));
      std::string                            vtk_messages;
      vtkNew<vtkCallbackCommand>             on_message;
      vtkSmartPointer<vtkXMLImageDataReader> reader =
        vtkSmartPointer<vtkXMLImageDataReader>::New();
      on_message->SetCallback(Geometry::collect_vtk_message);
      on_message->SetClientData(&vtk_messages);
      reader->AddObserver(vtkCommand::ErrorEvent, on_message);
      reader->AddObserver(vtkCommand::WarningEvent, on_message);
      AssertThrow(reader->CanReadFile(file.c_str()) != 0,
                  dealii::ExcMessage(where + ": '" + file +
                                     "' is not a VTK XML image file (.vti, "
                                     "<VTKFile type=\"ImageData\">)."));
      reader->SetFileName(file.c_str());
      reader->Update();
      vtkImageData *image = reader->GetOutput();
      AssertThrow(image != nullptr && image->GetNumberOfPoints() > 0 &&
                    reader->GetErrorCode() == 0 && vtk_messages.empty(),
                  dealii::ExcMessage(where + ": cannot read '" + file + "'" +
                                     (vtk_messages.empty()
                                        ? std::string(" (no points).")
                                        : ": " + vtk_messages)));
      // The messages of later calls go nowhere (vtk_messages ends here).
      reader->RemoveAllObservers();
      return reader;
    }

    /// The diffusion-tensor array of @p image (9 or 6 components).
    vtkDataArray *
    tensor_array(vtkImageData        *image,
                 const DTIParameters &params,
                 const std::string   &where)
    {
      const std::string &file       = params.file;
      vtkPointData      *point_data = image->GetPointData();
      vtkDataArray      *array =
        params.tensor_array.empty()
               ? point_data->GetTensors()
               : point_data->GetArray(params.tensor_array.c_str());
      if (array == nullptr)
        {
          const std::string names = Geometry::vtk_array_names(*point_data);
          fail(where + ": '" + file + "' has no point-data array " +
               (params.tensor_array.empty()
                  ? std::string("marked as the tensor attribute")
                  : "named '" + params.tensor_array + "'") +
               " (point-data arrays: " + (names.empty() ? "none" : names) +
               "). Set Fibres / DTI / Tensor array name.");
        }
      const int n_components = array->GetNumberOfComponents();
      AssertThrow(n_components == 9 || n_components == 6,
                  dealii::ExcMessage(
                    where + ": the array '" +
                    (array->GetName() != nullptr ? array->GetName() : "") +
                    "' of '" + file + "' has " + std::to_string(n_components) +
                    " components; a diffusion tensor needs 9 (row-major) or 6 "
                    "(xx, yy, zz, xy, yz, xz)."));
      return array;
    }

    /// The voxel grid of an image in the mesh frame.
    struct VoxelGrid
    {
      std::array<unsigned int, 3> n;     ///< voxels per axis
      std::array<int, 3>          first; ///< index of the first voxel
      /// Mesh point -> continuous voxel index (0 at the first voxel).
      dealii::Tensor<2, 3> index_matrix;
      dealii::Tensor<1, 3> index_offset;
      /// Linear part A of the image-to-mesh transform.
      dealii::Tensor<2, 3> A;
      dealii::Point<3>     box_lower, box_upper; ///< in the mesh frame

      /// "voxel (i, j, k)" of the flat index @p v, in the image's indices.
      std::string
      voxel_name(const std::uint64_t v) const
      {
        return "voxel (" + std::to_string(v % n[0] + first[0]) + ", " +
               std::to_string((v / n[0]) % n[1] + first[1]) + ", " +
               std::to_string(v / (std::uint64_t(n[0]) * n[1]) + first[2]) +
               ")";
      }
    };

    /// The grid of @p image: continuous voxel index r (0 at the first
    /// voxel) -> image physical point P r + p0 -> mesh point A (P r + p0) +
    /// b.
    VoxelGrid
    voxel_grid(vtkImageData        *image,
               const DTIParameters &params,
               const std::string   &where)
    {
      VoxelGrid grid;
      int       dims[3], extent[6];
      image->GetDimensions(dims);
      image->GetExtent(extent);
      for (unsigned int d = 0; d < 3; ++d)
        {
          AssertThrow(dims[d] >= 2,
                      dealii::ExcMessage(
                        where + ": '" + params.file +
                        "' has fewer than 2 voxels along axis " +
                        std::to_string(d) +
                        "; trilinear interpolation needs a 3-D image."));
          grid.n[d]     = dims[d];
          grid.first[d] = extent[2 * d];
        }
      vtkMatrix4x4   *index_to_physical = image->GetIndexToPhysicalMatrix();
      Matrix3         P, Am;
      Eigen::Vector3d p0, b;
      for (unsigned int i = 0; i < 3; ++i)
        {
          for (unsigned int j = 0; j < 3; ++j)
            {
              P(i, j)      = index_to_physical->GetElement(i, j);
              Am(i, j)     = params.image_to_mesh[4 * i + j];
              grid.A[i][j] = Am(i, j);
            }
          p0[i] = index_to_physical->GetElement(i, 3);
          b[i]  = params.image_to_mesh[4 * i + 3];
        }
      p0 += P * Eigen::Vector3d(extent[0], extent[2], extent[4]);
      const Matrix3 index_to_mesh = Am * P;
      AssertThrow(std::abs(index_to_mesh.determinant()) >
                    1e-12 * std::pow(index_to_mesh.norm(), 3),
                  dealii::ExcMessage(where + ": the voxel grid of '" +
                                     params.file +
                                     "' is degenerate (zero spacing or a "
                                     "singular direction matrix)."));
      const Matrix3         inverse = index_to_mesh.inverse();
      const Eigen::Vector3d offset  = -inverse * (Am * p0 + b);
      for (unsigned int i = 0; i < 3; ++i)
        {
          grid.index_offset[i] = offset[i];
          for (unsigned int j = 0; j < 3; ++j)
            grid.index_matrix[i][j] = inverse(i, j);
        }
      for (unsigned int d = 0; d < 3; ++d)
        {
          grid.box_lower[d] = std::numeric_limits<double>::max();
          grid.box_upper[d] = std::numeric_limits<double>::lowest();
        }
      for (unsigned int corner = 0; corner < 8; ++corner)
        {
          const Eigen::Vector3d r((corner & 1) ? grid.n[0] - 1 : 0,
                                  (corner & 2) ? grid.n[1] - 1 : 0,
                                  (corner & 4) ? grid.n[2] - 1 : 0);
          const Eigen::Vector3d x = index_to_mesh * r + Am * p0 + b;
          for (unsigned int d = 0; d < 3; ++d)
            {
              grid.box_lower[d] = std::min(grid.box_lower[d], x[d]);
              grid.box_upper[d] = std::max(grid.box_upper[d], x[d]);
            }
        }
      return grid;
    }

    /// The diffusion tensor of voxel @p v of @p array (9 or 6 components).
    Matrix3
    voxel_tensor(vtkDataArray &array, const std::uint64_t v)
    {
      std::array<double, 9> tuple;
      array.GetTuple(static_cast<vtkIdType>(v), tuple.data());
      Matrix3 D;
      if (array.GetNumberOfComponents() == 6)
        D = to_matrix(
          {{tuple[0], tuple[1], tuple[2], tuple[3], tuple[4], tuple[5]}});
      else
        for (unsigned int i = 0; i < 3; ++i)
          for (unsigned int j = 0; j < 3; ++j)
            D(i, j) = tuple[3 * i + j];
      return D;
    }

    /// log D of every voxel of an image, and which voxels give a frame.
    struct LogTensors
    {
      std::vector<std::array<double, 6>> logs;
      std::vector<std::uint8_t>          background; ///< D = 0
      std::vector<bool>                  valid;      ///< is_anisotropic()
      std::uint64_t                      n_valid = 0;
    };

    /// log D per voxel, once; throws naming the voxel at a tensor that is
    /// not finite, symmetric or positive definite.
    LogTensors
    log_tensors(vtkDataArray        &array,
                const VoxelGrid     &grid,
                const DTIParameters &params,
                const std::string   &where)
    {
      const std::string  &file = params.file;
      const std::uint64_t n_total =
        static_cast<std::uint64_t>(grid.n[0]) * grid.n[1] * grid.n[2];
      LogTensors result;
      result.logs.assign(n_total, {{0, 0, 0, 0, 0, 0}});
      result.background.assign(n_total, 0);
      result.valid.assign(n_total, false);
      Eigen::SelfAdjointEigenSolver<Matrix3> solver;
      for (std::uint64_t v = 0; v < n_total; ++v)
        {
          Matrix3 D = voxel_tensor(array, v);
          AssertThrow(D.allFinite(),
                      dealii::ExcMessage(where + ": the tensor at " +
                                         grid.voxel_name(v) + " of '" + file +
                                         "' has a NaN or infinite component."));
          const double norm = D.norm();
          if (norm == 0.0)
            {
              result.background[v] = 1;
              continue;
            }
          AssertThrow((D - D.transpose()).norm() <= 1e-3 * norm,
                      dealii::ExcMessage(where + ": the tensor at " +
                                         grid.voxel_name(v) + " of '" + file +
                                         "' is not symmetric."));
          D = 0.5 * (D + D.transpose());
          solver.compute(D);
          const Eigen::Vector3d l = solver.eigenvalues();
          if (!(l[0] > 0.0))
            fail(where + ": the tensor at " + grid.voxel_name(v) + " of '" +
                 file + "' is not positive definite (eigenvalues " +
                 format_number(l[0], digits) + ", " +
                 format_number(l[1], digits) + ", " +
                 format_number(l[2], digits) +
                 "). Set background voxels to zero and repair the others "
                 "(e.g. clamp the eigenvalues to a small positive value) "
                 "before import.");
          const Eigen::Vector3d log_l = l.array().log();
          result.logs[v] =
            to_components(solver.eigenvectors() * log_l.asDiagonal() *
                          solver.eigenvectors().transpose());
          result.valid[v] =
            is_anisotropic(l, params.minimum_fractional_anisotropy);
          if (result.valid[v])
            ++result.n_valid;
        }
      return result;
    }

    /// The nearest valid voxel of every voxel of a grid of @p n voxels: a
    /// multi-source breadth-first search over the 26 neighbours.
    std::vector<std::uint64_t>
    nearest_valid_voxels(const std::vector<bool>           &valid,
                         const std::array<unsigned int, 3> &n)
    {
      constexpr std::uint64_t none = std::numeric_limits<std::uint64_t>::max();
      std::vector<std::uint64_t> nearest(valid.size(), none);
      std::deque<std::uint64_t>  queue;
      for (std::uint64_t v = 0; v < valid.size(); ++v)
        if (valid[v])
          {
            nearest[v] = v;
            queue.push_back(v);
          }
      while (!queue.empty())
        {
          const std::uint64_t v = queue.front();
          queue.pop_front();
          const long i = v % n[0], j = (v / n[0]) % n[1],
                     k = v / (std::uint64_t(n[0]) * n[1]);
          for (long dk = -1; dk <= 1; ++dk)
            for (long dj = -1; dj <= 1; ++dj)
              for (long di = -1; di <= 1; ++di)
                {
                  const long ii = i + di, jj = j + dj, kk = k + dk;
                  if (ii < 0 || jj < 0 || kk < 0 || ii >= long(n[0]) ||
                      jj >= long(n[1]) || kk >= long(n[2]))
                    continue;
                  const std::uint64_t w = ii + n[0] * (jj + n[1] * kk);
                  if (nearest[w] == none)
                    {
                      nearest[w] = nearest[v];
                      queue.push_back(w);
                    }
                }
        }
      return nearest;
    }
  } // namespace

  DTIField::DTIField(const DTIParameters &parameters)
    : params(parameters)
  {
    const std::string where  = "Fibres / DTI / File";
    const auto        reader = read_image(params.file, where);
    vtkImageData     *image  = reader->GetOutput();
    vtkDataArray     *array  = tensor_array(image, params, where);
    const VoxelGrid   grid   = voxel_grid(image, params, where);
    n                        = grid.n;
    index_matrix             = grid.index_matrix;
    index_offset             = grid.index_offset;
    A                        = grid.A;
    box_lower                = grid.box_lower;
    box_upper                = grid.box_upper;

    LogTensors tensors = log_tensors(*array, grid, params, where);
    logs               = std::move(tensors.logs);
    background         = std::move(tensors.background);
    n_valid            = tensors.n_valid;
    AssertThrow(n_valid > 0,
                dealii::ExcMessage(
                  where + ": '" + params.file +
                  "' has no voxel with a tensor of fractional anisotropy >= " +
                  format_number(params.minimum_fractional_anisotropy, digits) +
                  " (Fibres / DTI / Minimum fractional anisotropy) and three "
                  "distinct eigenvalues."));
    nearest_valid = nearest_valid_voxels(tensors.valid, n);
  }

  bool
  DTIField::log_mean(const dealii::Point<3> &X, std::array<double, 6> &L) const
  {
    const dealii::Tensor<1, 3>  y         = index_matrix * X + index_offset;
    constexpr double            tolerance = 1e-9;
    std::array<unsigned int, 3> i0;
    std::array<double, 3>       w;
    for (unsigned int d = 0; d < 3; ++d)
      {
        const double top = n[d] - 1.0;
        if (!(y[d] >= -tolerance && y[d] <= top + tolerance))
          return false;
        const double yd = std::min(std::max(y[d], 0.0), top);
        i0[d]           = std::min(static_cast<unsigned int>(yd), n[d] - 2);
        w[d]            = yd - i0[d];
      }
    L.fill(0.0);
    double              weight_sum = 0.0;
    const std::uint64_t base =
      i0[0] + std::uint64_t(n[0]) * (i0[1] + std::uint64_t(n[1]) * i0[2]);
    for (unsigned int corner = 0; corner < 8; ++corner)
      {
        const unsigned int a = corner & 1, b = (corner >> 1) & 1,
                           c = (corner >> 2) & 1;
        const std::uint64_t v =
          base + a + std::uint64_t(n[0]) * (b + std::uint64_t(n[1]) * c);
        if (background[v])
          continue;
        const double weight = (a ? w[0] : 1.0 - w[0]) *
                              (b ? w[1] : 1.0 - w[1]) * (c ? w[2] : 1.0 - w[2]);
        if (weight == 0.0)
          continue;
        weight_sum += weight;
        for (unsigned int m = 0; m < 6; ++m)
          L[m] += weight * logs[v][m];
      }
    // Mostly background: the point is outside the data.
    if (weight_sum < 0.5)
      return false;
    for (double &l : L)
      l /= weight_sum;
    return true;
  }

  DTISample
  DTIField::frame_from_log(const std::array<double, 6> &L) const
  {
    Eigen::SelfAdjointEigenSolver<Matrix3> solver;
    solver.computeDirect(to_matrix(L));
    const Eigen::Vector3d mu = solver.eigenvalues(); // ascending
    // exp(L) has the eigenvalues exp(mu); FA and the gaps are scale free.
    const Eigen::Vector3d l = (mu.array() - mu[2]).exp();

    DTISample sample;
    sample.fractional_anisotropy = fractional_anisotropy(l);
    sample.status = is_anisotropic(l, params.minimum_fractional_anisotropy)
                      ? DTIStatus::valid
                      : DTIStatus::low_anisotropy;
    dealii::Tensor<1, 3> f_image, s_image;
    for (unsigned int d = 0; d < 3; ++d)
      {
        f_image[d] = solver.eigenvectors()(d, 2);
        s_image[d] = solver.eigenvectors()(d, 1);
      }
    FibreBasis &basis = sample.basis;
    basis.f           = A * f_image;
    basis.f /= basis.f.norm();
    basis.s = A * s_image;
    basis.s -= (basis.s * basis.f) * basis.f;
    basis.s /= basis.s.norm();
    fix_sign(basis.f);
    fix_sign(basis.s);
    basis.n = dealii::cross_product_3d(basis.f, basis.s);
    return sample;
  }

  std::uint64_t
  DTIField::closest_voxel(const dealii::Point<3> &X) const
  {
    const dealii::Tensor<1, 3>   y = index_matrix * X + index_offset;
    std::array<std::uint64_t, 3> i;
    for (unsigned int d = 0; d < 3; ++d)
      {
        const double yd = std::min(std::max(y[d], 0.0), n[d] - 1.0);
        i[d]            = static_cast<std::uint64_t>(std::lround(yd));
      }
    return i[0] + n[0] * (i[1] + n[1] * i[2]);
  }

  DTISample
  DTIField::sample(const dealii::Point<3> &X) const
  {
    std::array<double, 6> L;
    DTISample             result;
    if (log_mean(X, L))
      {
        result = frame_from_log(L);
        if (result.status == DTIStatus::valid)
          return result;
      }
    else
      result.status = DTIStatus::outside;
    result.basis = frame_from_log(logs[nearest_valid[closest_voxel(X)]]).basis;
    return result;
  }

  FibreBasis
  DTIField::operator()(const dealii::Point<3> &X)
  {
    const DTISample result = sample(X);
    counts.add(result.status);
    return result.basis;
  }

  const DTIStatistics &
  DTIField::statistics() const
  {
    return counts;
  }

  dealii::SymmetricTensor<2, 3>
  DTIField::tensor(const dealii::Point<3> &X) const
  {
    std::array<double, 6> L;
    AssertThrow(log_mean(X, L),
                dealii::ExcMessage("Fibres / DTI: the point " +
                                   Geometry::format_point(X, digits) +
                                   " is outside the data of '" + params.file +
                                   "'."));
    Eigen::SelfAdjointEigenSolver<Matrix3> solver(to_matrix(L));
    const Eigen::Vector3d l = solver.eigenvalues().array().exp();
    const Matrix3         D = solver.eigenvectors() * l.asDiagonal() *
                      solver.eigenvectors().transpose();
    dealii::SymmetricTensor<2, 3> result;
    for (unsigned int i = 0; i < 3; ++i)
      for (unsigned int j = i; j < 3; ++j)
        result[i][j] = 0.5 * (D(i, j) + D(j, i));
    return result;
  }

  std::array<unsigned int, 3>
  DTIField::n_voxels() const
  {
    return n;
  }

  std::uint64_t
  DTIField::n_valid_voxels() const
  {
    return n_valid;
  }

  std::pair<dealii::Point<3>, dealii::Point<3>>
  DTIField::mesh_bounding_box() const
  {
    return {box_lower, box_upper};
  }

  const DTIParameters &
  DTIField::parameters() const
  {
    return params;
  }

  // ---------------------------------------------------------------------------
  // The generator

  FibreField
  create_dti_fibre_field(const DTIParameters                            &params,
                         const dealii::Triangulation<3, 3>              &tria,
                         const std::function<void(const std::string &)> &report)
  {
    const auto     field = std::make_shared<const DTIField>(params);
    const MPI_Comm comm  = tria.get_communicator();

    // Sample the Gauss points of 2 per direction of the straight-sided cells
    // (8 in a hexahedron, 4 in a tetrahedron).
    DTIStatistics       local;
    std::vector<double> lower(3, std::numeric_limits<double>::max());
    std::vector<double> upper(3, std::numeric_limits<double>::lowest());
    for (const auto &cell : tria.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          const dealii::ReferenceCell shape = cell->reference_cell();
          const dealii::Quadrature<3> points =
            shape.get_gauss_type_quadrature<3>(2);
          for (const auto &unit : points.get_points())
            {
              dealii::Point<3> X;
              for (const unsigned int v : cell->vertex_indices())
                X += shape.d_linear_shape_function(unit, v) * cell->vertex(v);
              local.add(field->sample(X).status);
            }
          for (const unsigned int v : cell->vertex_indices())
            for (unsigned int d = 0; d < 3; ++d)
              {
                lower[d] = std::min(lower[d], cell->vertex(v)[d]);
                upper[d] = std::max(upper[d], cell->vertex(v)[d]);
              }
        }
    const std::vector<std::uint64_t> local_counts = {local.n_points,
                                                     local.n_outside,
                                                     local.n_low_anisotropy};
    std::vector<std::uint64_t>       global_counts(3);
    dealii::Utilities::MPI::sum(local_counts, comm, global_counts);
    DTIStatistics global;
    global.n_points         = global_counts[0];
    global.n_outside        = global_counts[1];
    global.n_low_anisotropy = global_counts[2];

    const auto percent = [](const double fraction) {
      return format_number(100.0 * fraction, 3) + " %";
    };
    const auto   n        = field->n_voxels();
    const double fraction = global.rejected_fraction();
    if (report)
      report("Fibres / DTI: '" + params.file + "', " + std::to_string(n[0]) +
             " x " + std::to_string(n[1]) + " x " + std::to_string(n[2]) +
             " voxels (" + std::to_string(field->n_valid_voxels()) +
             " valid); of " + std::to_string(global.n_points) +
             " mesh points " + std::to_string(global.n_outside) +
             " outside the data, " + std::to_string(global.n_low_anisotropy) +
             " nearly isotropic (" + percent(fraction) + " rejected, limit " +
             percent(params.maximum_rejected_fraction) +
             "); rejected points take the nearest valid voxel's frame.");

    if (fraction > params.maximum_rejected_fraction)
      {
        dealii::Point<3> mesh_lower, mesh_upper;
        for (unsigned int d = 0; d < 3; ++d)
          {
            mesh_lower[d] = dealii::Utilities::MPI::min(lower[d], comm);
            mesh_upper[d] = dealii::Utilities::MPI::max(upper[d], comm);
          }
        const auto box = field->mesh_bounding_box();
        fail("Fibres / DTI: " + percent(fraction) + " of the mesh points (" +
             std::to_string(global.n_outside) + " outside the data of '" +
             params.file + "', " + std::to_string(global.n_low_anisotropy) +
             " with fractional anisotropy below " +
             format_number(params.minimum_fractional_anisotropy, digits) +
             ") are rejected, more than Fibres / DTI / Maximum rejected "
             "fraction = " +
             percent(params.maximum_rejected_fraction) + ". The mesh spans " +
             Geometry::format_point(mesh_lower, digits) + " to " +
             Geometry::format_point(mesh_upper, digits) + " mm, the image " +
             Geometry::format_point(box.first, digits) + " to " +
             Geometry::format_point(box.second, digits) +
             " mm in mesh coordinates: check Fibres / DTI / Image to mesh "
             "transform and the image extent (or lower Minimum fractional "
             "anisotropy).");
      }

    return [field](const dealii::Triangulation<3, 3>::active_cell_iterator &,
                   const std::vector<dealii::Point<3>> &points,
                   std::vector<FibreBasis>             &bases) {
      bases.resize(points.size());
      for (unsigned int i = 0; i < points.size(); ++i)
        {
          bases[i] = field->sample(points[i]).basis;
          try
            {
              validate(bases[i], "a point");
            }
          catch (const std::exception &)
            {
              validate(bases[i],
                       Geometry::format_point(points[i], digits) +
                         " (dti generator)");
            }
        }
    };
  }
} // namespace systole::Fibres

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_q.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/tria.h>

#include "base/errors.h"
#include "fibres/dti_import.h"
#include "fibres/fibre_field.h"
#include "geometry/ellipsoid.h"
#include "geometry/mesh.h"

#include <catch2/catch.hpp>
#include <vtkDoubleArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkXMLImageDataWriter.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <random>

using namespace systole;
using dealii::Point;
using dealii::Tensor;

namespace
{
  constexpr double degree = M_PI / 180.0;

  /// A file in the working directory (the build tree under ctest), removed at
  /// the end of the test.
  struct ScratchFile
  {
    explicit ScratchFile(const std::string &name)
      : name("dti_import_test_" + name)
    {}
    ~ScratchFile()
    {
      std::filesystem::remove(name);
    }
    std::string name;
  };

  using TensorFunction =
    std::function<Tensor<2, 3>(unsigned int, unsigned int, unsigned int)>;

  /// Write a tensor image with VTK's own writer: @p n voxels, the voxel
  /// (i, j, k) at origin + (i, j, k) * spacing, tensor D(i, j, k) stored with
  /// 9 or 6 (xx, yy, zz, xy, yz, xz) components.
  void
  write_image(const std::string                 &file,
              const std::array<unsigned int, 3> &n,
              const Point<3>                    &origin,
              const Tensor<1, 3>                &spacing,
              const TensorFunction              &D,
              const int                          n_components = 9,
              const std::string                 &name         = "tensors")
  {
    vtkNew<vtkImageData> image;
    image->SetDimensions(n[0], n[1], n[2]);
    image->SetOrigin(origin[0], origin[1], origin[2]);
    image->SetSpacing(spacing[0], spacing[1], spacing[2]);
    vtkNew<vtkDoubleArray> array;
    array->SetName(name.c_str());
    array->SetNumberOfComponents(n_components);
    array->SetNumberOfTuples(vtkIdType(n[0]) * n[1] * n[2]);
    for (unsigned int k = 0; k < n[2]; ++k)
      for (unsigned int j = 0; j < n[1]; ++j)
        for (unsigned int i = 0; i < n[0]; ++i)
          {
            const Tensor<2, 3>  d = D(i, j, k);
            std::vector<double> tuple;
            if (n_components == 6)
              tuple = {d[0][0], d[1][1], d[2][2], d[0][1], d[1][2], d[0][2]};
            else
              for (unsigned int a = 0; a < 3; ++a)
                for (unsigned int b = 0; b < 3; ++b)
                  tuple.push_back(d[a][b]);
            tuple.resize(n_components, 0.0);
            array->SetTuple(i + n[0] * (j + n[1] * k), tuple.data());
          }
    image->GetPointData()->AddArray(array);
    vtkNew<vtkXMLImageDataWriter> writer;
    writer->SetFileName(file.c_str());
    writer->SetInputData(image);
    REQUIRE(writer->Write() == 1);
  }

  /// R diag(l) R^T for the frame (e1, e2, e3) = columns of R.
  Tensor<2, 3>
  tensor_from_frame(const Tensor<1, 3>          &e1,
                    const Tensor<1, 3>          &e2,
                    const Tensor<1, 3>          &e3,
                    const std::array<double, 3> &l)
  {
    return l[0] * dealii::outer_product(e1, e1) +
           l[1] * dealii::outer_product(e2, e2) +
           l[2] * dealii::outer_product(e3, e3);
  }

  /// Rotation by @p angle about the unit vector @p axis.
  Tensor<2, 3>
  rotation(const Tensor<1, 3> &axis, const double angle)
  {
    Tensor<2, 3> K;
    K[0][1] = -axis[2];
    K[0][2] = axis[1];
    K[1][0] = axis[2];
    K[1][2] = -axis[0];
    K[2][0] = -axis[1];
    K[2][1] = axis[0];
    const Tensor<2, 3> I(dealii::unit_symmetric_tensor<3>());
    return I + std::sin(angle) * K + (1.0 - std::cos(angle)) * K * K;
  }

  /// Sign-free angle between two directions [degrees].
  double
  angle_between(const Tensor<1, 3> &a, const Tensor<1, 3> &b)
  {
    const double c = std::abs(a * b) / (a.norm() * b.norm());
    return std::acos(std::min(1.0, c)) / degree;
  }

  Tensor<1, 3>
  unit(const double x, const double y, const double z)
  {
    Tensor<1, 3> v({x, y, z});
    return v / v.norm();
  }

  double
  fractional_anisotropy(const std::array<double, 3> &l)
  {
    const double mean = (l[0] + l[1] + l[2]) / 3.0;
    double       dev = 0.0, norm = 0.0;
    for (const double x : l)
      {
        dev += (x - mean) * (x - mean);
        norm += x * x;
      }
    return std::sqrt(1.5 * dev / norm);
  }

  /// The one-line message of the exception @p f throws ("" if none).
  template <class F>
  std::string
  error_of(const F &f)
  {
    try
      {
        f();
      }
    catch (const std::exception &e)
      {
        return systole::one_line_message(e);
      }
    return "";
  }

  Fibres::DTIParameters
  parameters_for(const std::string &file)
  {
    Fibres::DTIParameters p;
    p.file = file;
    return p;
  }

  /// Matrix exponential of a symmetric tensor.
  Tensor<2, 3>
  exp_symmetric(const dealii::SymmetricTensor<2, 3> &L)
  {
    const auto eig =
      dealii::eigenvectors(L, dealii::SymmetricTensorEigenvectorMethod::jacobi);
    Tensor<2, 3> result;
    for (const auto &[value, vector] : eig)
      result += std::exp(value) * dealii::outer_product(vector, vector);
    return result;
  }

  /// The analytic helix rule turned into tensors on a grid over the Land
  /// ventricle (spacing @p h), eigenvalues (1, 0.7, 0.49) along (f, s, n);
  /// log-domain noise sigma (Z + Z^T) / 2 with a fixed seed; isotropic
  /// tensors far from the wall (t outside [-0.5, 1.5] or 1 mm above the base).
  void
  write_land_image(const std::string           &file,
                   const Fibres::AnalyticHelix &helix,
                   const Geometry::LVShape     &shape,
                   const double                 h,
                   const double                 sigma)
  {
    const Point<3>              lower(-shape.epi_short_radius - 1,
                         -shape.epi_short_radius - 1,
                         -shape.epi_long_radius - 1);
    const Point<3>              upper(shape.epi_short_radius + 1,
                         shape.epi_short_radius + 1,
                         shape.base_height + 1);
    std::array<unsigned int, 3> n;
    for (unsigned int d = 0; d < 3; ++d)
      n[d] =
        static_cast<unsigned int>(std::ceil((upper[d] - lower[d]) / h)) + 1;
    const Geometry::EllipsoidalWallManifold manifold(shape);
    const std::array<double, 3>             l = {{1.0, 0.7, 0.49}};
    std::mt19937                            rng(42);
    std::normal_distribution<double>        normal;
    write_image(file,
                n,
                lower,
                Tensor<1, 3>({h, h, h}),
                [&](auto i, auto j, auto k) {
                  Point<3> X = lower + h * Point<3>(i, j, k);
                  // The analytic frame is undefined on the axis: step off it.
                  if (std::hypot(X[0], X[1]) < 1e-6)
                    X[0] = 1e-3;
                  Tensor<2, 3> z;
                  for (unsigned int a = 0; a < 3; ++a)
                    for (unsigned int b = 0; b < 3; ++b)
                      z[a][b] = normal(rng);
                  const double t = manifold.transmural_coordinate(X);
                  if (t < -0.5 || t > 1.5 || X[2] > shape.base_height + 1.0)
                    return Tensor<2, 3>(dealii::unit_symmetric_tensor<3>());
                  const auto                    b = helix(X);
                  dealii::SymmetricTensor<2, 3> L =
                    dealii::symmetrize(tensor_from_frame(
                      b.f,
                      b.s,
                      b.n,
                      {{std::log(l[0]), std::log(l[1]), std::log(l[2])}}));
                  L += sigma * dealii::symmetrize(z);
                  return exp_symmetric(L);
                });
  }

  /// Fibre and sheet angle errors [degrees] of the dti generator against the
  /// analytic rule at the QGauss(3) points of the Land ventricle (one global
  /// refinement, MappingQ2).
  struct RoundTrip
  {
    std::vector<double> fibre_errors, sheet_errors;
    std::string         report;
  };

  RoundTrip
  land_round_trip(const std::string &file, const Fibres::AnalyticHelix &helix)
  {
    Geometry::Parameters geometry; // the Land ventricle
    geometry.global_refinements = 1;
    dealii::Triangulation<3> tria;
    Geometry::create_mesh(geometry, tria);

    RoundTrip                result;
    const Fibres::FibreField fibres =
      Fibres::create_dti_fibre_field(parameters_for(file),
                                     tria,
                                     [&](const std::string &line) {
                                       result.report = line;
                                     });
    const dealii::FE_Q<3>           fe(1);
    const dealii::MappingQ<3>       mapping(2);
    const dealii::QGauss<3>         quadrature(3);
    dealii::FEValues<3>             fe_values(mapping,
                                  fe,
                                  quadrature,
                                  dealii::update_quadrature_points);
    std::vector<Fibres::FibreBasis> bases;
    for (const auto &cell : tria.active_cell_iterators())
      {
        fe_values.reinit(cell);
        const auto &points = fe_values.get_quadrature_points();
        fibres(cell, points, bases);
        for (unsigned int q = 0; q < points.size(); ++q)
          {
            const auto exact = helix(points[q]);
            result.fibre_errors.push_back(angle_between(bases[q].f, exact.f));
            result.sheet_errors.push_back(angle_between(bases[q].s, exact.s));
          }
      }
    return result;
  }

  struct ErrorSummary
  {
    double mean, max, fraction_below_2;
  };

  ErrorSummary
  summarize(const std::vector<double> &errors)
  {
    ErrorSummary s{0.0, 0.0, 0.0};
    for (const double e : errors)
      {
        s.mean += e;
        s.max = std::max(s.max, e);
        s.fraction_below_2 += (e <= 2.0);
      }
    s.mean /= errors.size();
    s.fraction_below_2 /= errors.size();
    return s;
  }
} // namespace

TEST_CASE("A constant tensor field is recovered between voxels, through the "
          "image-to-mesh transform",
          "[dti]")
{
  const int         n_components = GENERATE(9, 6);
  const ScratchFile file("constant_" + std::to_string(n_components) + ".vti");
  // Principal axes of the data, in the image frame.
  const Tensor<2, 3> R  = rotation(unit(1, 2, 3), 0.7);
  const Tensor<1, 3> e1 = R * unit(1, 0, 0), e2 = R * unit(0, 1, 0),
                     e3         = R * unit(0, 0, 1);
  const std::array<double, 3> l = {{3e-3, 2e-3, 1e-3}};
  const Point<3>              origin(1, 2, 3);
  const Tensor<1, 3>          spacing({0.5, 0.7, 0.9});
  write_image(
    file.name,
    {{4, 5, 6}},
    origin,
    spacing,
    [&](auto, auto, auto) { return tensor_from_frame(e1, e2, e3, l); },
    n_components);

  // The mesh is the image rotated by Q and shifted by b.
  const Tensor<2, 3>    Q = rotation(unit(-1, 0.5, 2), 1.1);
  const Tensor<1, 3>    b({10, -20, 5});
  Fibres::DTIParameters params = parameters_for(file.name);
  for (unsigned int i = 0; i < 3; ++i)
    {
      for (unsigned int j = 0; j < 3; ++j)
        params.image_to_mesh[4 * i + j] = Q[i][j];
      params.image_to_mesh[4 * i + 3] = b[i];
    }
  Fibres::DTIField field(params);
  CHECK(field.n_voxels() == std::array<unsigned int, 3>{{4, 5, 6}});
  CHECK(field.n_valid_voxels() == 4 * 5 * 6);

  std::mt19937                           rng(42);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  for (unsigned int p = 0; p < 50; ++p)
    {
      Point<3> x_image = origin;
      for (unsigned int d = 0; d < 3; ++d)
        x_image[d] += uniform(rng) * spacing[d] * (d == 0 ? 3 : d == 1 ? 4 : 5);
      const Point<3> X      = Point<3>(Q * x_image + b);
      const auto     sample = field.sample(X);
      REQUIRE(sample.status == Fibres::DTIStatus::valid);
      CHECK_NOTHROW(Fibres::validate(sample.basis, "test"));
      CHECK(angle_between(sample.basis.f, Q * e1) < 1e-6);
      CHECK(angle_between(sample.basis.s, Q * e2) < 1e-6);
      CHECK(sample.fractional_anisotropy ==
            Approx(fractional_anisotropy(l)).epsilon(1e-10));
      // The documented sign convention.
      CHECK(sample.basis.f[2] > 0.0);
      CHECK(sample.basis.s[2] > 0.0);
    }
  // Outside the image.
  const auto outside = field.sample(Point<3>(Q * Point<3>(0, 0, 0) + b));
  CHECK(outside.status == Fibres::DTIStatus::outside);
  CHECK(angle_between(outside.basis.f, Q * e1) < 1e-6);
}

TEST_CASE("A linearly rotating field is recovered within 2 degrees between "
          "voxels",
          "[dti]")
{
  const ScratchFile file("rotating.vti");
  // The fibre turns about z by 15 degrees per voxel along x.
  const double turn = 15.0 * degree;
  const auto   f_at = [&](const double x) {
    return unit(std::cos(turn * x), std::sin(turn * x), 0.0);
  };
  write_image(file.name,
              {{9, 3, 3}},
              Point<3>(),
              Tensor<1, 3>({1, 1, 1}),
              [&](auto i, auto, auto) {
                const Tensor<1, 3> f = f_at(i);
                return tensor_from_frame(f,
                                         unit(-f[1], f[0], 0),
                                         unit(0, 0, 1),
                                         {{2.0, 1.0, 0.5}});
              });
  Fibres::DTIField field(parameters_for(file.name));
  double           max_error = 0.0;
  for (double x = 0.0; x <= 8.0; x += 0.125)
    for (const double y : {0.3, 1.5})
      {
        const auto sample = field.sample(Point<3>(x, y, 0.8));
        REQUIRE(sample.status == Fibres::DTIStatus::valid);
        max_error = std::max(max_error, angle_between(sample.basis.f, f_at(x)));
      }
  INFO("maximum fibre angle error " << max_error << " degrees");
  CHECK(max_error < 2.0);
  // The midpoint of two voxels is exact by symmetry.
  CHECK(angle_between(field.sample(Point<3>(3.5, 1, 1)).basis.f, f_at(3.5)) <
        1e-6);
}

TEST_CASE("Log-Euclidean interpolation: rotation angle and determinant of "
          "the mean of two tensors",
          "[dti]")
{
  const ScratchFile           file("two_tensors.vti");
  const std::array<double, 3> l      = {{3.0, 1.5, 0.5}};
  const double                c      = 4.0; // the second tensor is 4 x larger
  const double                theta0 = 10 * degree, theta1 = 70 * degree;
  const std::function<Tensor<2, 3>(double, double)> D = [&](double theta,
                                                            double scale) {
    const Tensor<2, 3> R = rotation(unit(0, 0, 1), theta);
    return scale * tensor_from_frame(R * unit(1, 0, 0),
                                     R * unit(0, 1, 0),
                                     unit(0, 0, 1),
                                     l);
  };
  write_image(file.name,
              {{2, 2, 2}},
              Point<3>(),
              Tensor<1, 3>({1, 1, 1}),
              [&](auto i, auto, auto) {
                return i == 0 ? D(theta0, 1.0) : D(theta1, c);
              });
  const Fibres::DTIField field(parameters_for(file.name));
  const double           det0 = dealii::determinant(D(theta0, 1.0)),
               det1           = dealii::determinant(D(theta1, c));
  for (const double w : {0.0, 0.25, 0.5, 0.8, 1.0})
    {
      const Point<3> X(w, 0.3, 0.6);
      // Geometric interpolation of the determinant: exp(tr(mean of logs)).
      CHECK(dealii::determinant(field.tensor(X)) ==
            Approx(std::pow(det0, 1 - w) * std::pow(det1, w)).epsilon(1e-10));
    }
  // At the midpoint the principal axis is at the mean angle.
  const auto mid = field.sample(Point<3>(0.5, 0.5, 0.5));
  const auto R   = rotation(unit(0, 0, 1), 0.5 * (theta0 + theta1));
  CHECK(angle_between(mid.basis.f, R * unit(1, 0, 0)) < 1e-8);
  CHECK(angle_between(mid.basis.s, R * unit(0, 1, 0)) < 1e-8);
  // The log-Euclidean mean of these two is c^(1/2) times a rotated tensor
  // with the same eigenvalue product.
  CHECK(dealii::trace(field.tensor(Point<3>(0.5, 0.5, 0.5))) <
        std::sqrt(c) * (l[0] + l[1] + l[2]));
}

TEST_CASE("Points outside the data and on isotropic tensors are counted, get "
          "the nearest valid voxel's frame, and stop the generator above the "
          "limit",
          "[dti]")
{
  const ScratchFile file("counting.vti");
  // Voxels x = 0..10: background (zero) at x = 0, isotropic for x <= 4,
  // anisotropic along (1, 1, 0) for x >= 5.
  const Tensor<1, 3> f = unit(1, 1, 0), s = unit(-1, 1, 0);
  const Tensor<2, 3> anisotropic =
    tensor_from_frame(f, s, unit(0, 0, 1), {{10.0, 1.0, 0.1}});
  write_image(file.name,
              {{11, 2, 2}},
              Point<3>(),
              Tensor<1, 3>({1, 1, 1}),
              [&](auto i, auto, auto) {
                if (i == 0)
                  return Tensor<2, 3>();
                return i <= 4 ? Tensor<2, 3>(dealii::unit_symmetric_tensor<3>())
                              : anisotropic;
              });

  SECTION("DTIField counts by status")
  {
    Fibres::DTIField field(parameters_for(file.name));
    CHECK(field.n_valid_voxels() == 6 * 4);
    const auto status = [&](const double x) {
      return field.sample(Point<3>(x, 0.5, 0.5)).status;
    };
    CHECK(status(0.2) == Fibres::DTIStatus::outside); // background
    CHECK(status(0.6) == Fibres::DTIStatus::low_anisotropy);
    CHECK(status(2.0) == Fibres::DTIStatus::low_anisotropy);
    CHECK(status(6.0) == Fibres::DTIStatus::valid);
    CHECK(status(-0.1) == Fibres::DTIStatus::outside); // beyond the extent
    CHECK(status(10.5) == Fibres::DTIStatus::outside);
    CHECK(field.sample(Point<3>(5, 1.5, 0.5)).status ==
          Fibres::DTIStatus::outside);

    // Rejected points take the frame of the nearest valid voxel.
    for (const double x : {-3.0, 0.2, 2.0, 12.0})
      {
        const auto basis = field(Point<3>(x, 0.5, 0.5));
        CHECK_NOTHROW(Fibres::validate(basis, "test"));
        CHECK(angle_between(basis.f, f) < 1e-8);
        CHECK(angle_between(basis.s, s) < 1e-8);
      }
    field(Point<3>(7, 0.5, 0.5));
    CHECK(field.statistics().n_points == 5);
    CHECK(field.statistics().n_outside == 3);
    CHECK(field.statistics().n_low_anisotropy == 1);
    CHECK(field.statistics().rejected_fraction() == Approx(0.8));
  }

  SECTION("The generator reports the counts at the Gauss points of a mesh")
  {
    // 14 unit cells along x: cells 0-3 lie in the isotropic part (cell 0
    // partly in the background), 4-9 in the anisotropic part, 10-13 outside.
    dealii::Triangulation<3> tria;
    dealii::GridGenerator::subdivided_hyper_rectangle(tria,
                                                      {14, 1, 1},
                                                      Point<3>(0, 0, 0),
                                                      Point<3>(14, 1, 1));
    auto        params = parameters_for(file.name);
    std::string report;
    const auto  print = [&](const std::string &line) { report = line; };

    params.maximum_rejected_fraction = 0.6;
    Fibres::FibreField fibres;
    REQUIRE_NOTHROW(fibres =
                      Fibres::create_dti_fibre_field(params, tria, print));
    INFO(report);
    // Cell 0: its 4 points at x = 0.21 are background (outside), the 4 at
    // x = 0.79 isotropic.
    CHECK_THAT(report,
               Catch::Contains("of 112 mesh points 36 outside the data, 28 "
                               "nearly isotropic (57.1 % rejected"));
    std::vector<Fibres::FibreBasis> bases;
    for (const auto &cell : tria.active_cell_iterators())
      {
        const std::vector<Point<3>> points = {cell->center()};
        fibres(cell, points, bases);
        REQUIRE(bases.size() == 1);
        CHECK(angle_between(bases[0].f, f) < 1e-8);
      }

    params.maximum_rejected_fraction = 0.5;
    CHECK_THAT(error_of(
                 [&] { Fibres::create_dti_fibre_field(params, tria, print); }),
               Catch::Contains(file.name) && Catch::Contains("57.1 %") &&
                 Catch::Contains("Maximum rejected fraction = 50 %") &&
                 Catch::Contains("Image to mesh transform"));
  }
}

TEST_CASE("Missing or broken tensor images give clear errors", "[dti]")
{
  const std::array<unsigned int, 3> n        = {{3, 3, 3}};
  const auto                        identity = [](auto, auto, auto) {
    return Tensor<2, 3>(dealii::unit_symmetric_tensor<3>());
  };

  SECTION("missing file")
  {
    CHECK_THAT(error_of(
                 [&] { Fibres::DTIField(parameters_for("no_such_dti.vti")); }),
               Catch::Contains("Fibres / DTI / File") &&
                 Catch::Contains("no_such_dti.vti") &&
                 Catch::Contains("no such file"));
    CHECK_THAT(error_of([&] { Fibres::DTIField(parameters_for("")); }),
               Catch::Contains("is empty"));
  }
  SECTION("not a VTK image")
  {
    const ScratchFile file("not_an_image.vti");
    std::ofstream(file.name) << "hello\n";
    CHECK_THAT(error_of([&] { Fibres::DTIField(parameters_for(file.name)); }),
               Catch::Contains("not a VTK XML image file"));
  }
  SECTION("no tensor array")
  {
    const ScratchFile file("no_array.vti");
    write_image(file.name,
                n,
                Point<3>(),
                Tensor<1, 3>({1, 1, 1}),
                identity,
                9,
                "other");
    CHECK_THAT(error_of([&] { Fibres::DTIField(parameters_for(file.name)); }),
               Catch::Contains("no point-data array named 'tensors'") &&
                 Catch::Contains("'other'") &&
                 Catch::Contains("Tensor array name"));
  }
  SECTION("wrong number of components")
  {
    const ScratchFile file("vectors.vti");
    write_image(file.name, n, Point<3>(), Tensor<1, 3>({1, 1, 1}), identity, 3);
    CHECK_THAT(error_of([&] { Fibres::DTIField(parameters_for(file.name)); }),
               Catch::Contains("3 components"));
  }
  SECTION("a tensor that is not positive definite")
  {
    const ScratchFile file("indefinite.vti");
    write_image(file.name,
                n,
                Point<3>(),
                Tensor<1, 3>({1, 1, 1}),
                [](auto i, auto j, auto k) {
                  Tensor<2, 3> D(dealii::unit_symmetric_tensor<3>());
                  if (i == 1 && j == 2 && k == 0)
                    D[2][2] = -0.1;
                  return D;
                });
    CHECK_THAT(error_of([&] { Fibres::DTIField(parameters_for(file.name)); }),
               Catch::Contains("voxel (1, 2, 0)") &&
                 Catch::Contains("not positive definite"));
  }
  SECTION("only isotropic tensors")
  {
    const ScratchFile file("isotropic.vti");
    write_image(file.name, n, Point<3>(), Tensor<1, 3>({1, 1, 1}), identity);
    CHECK_THAT(error_of([&] { Fibres::DTIField(parameters_for(file.name)); }),
               Catch::Contains("has no voxel"));
  }
}

TEST_CASE("Files in the format of scripts/make_synthetic_dti.py are read "
          "(6 symmetric components in base64 or ASCII)",
          "[dti]")
{
  // D = [[2, 1, 0], [1, 2, 0], [0, 0, 0.5]] in all 8 voxels: f = (1, 1, 0) /
  // sqrt 2, s = (-1, 1, 0) / sqrt 2 (signs by the convention), n = e_z.
  const std::string head =
    "<?xml version=\"1.0\"?>\n<VTKFile type=\"ImageData\" version=\"1.0\" "
    "byte_order=\"LittleEndian\" header_type=\"UInt64\">\n<ImageData "
    "WholeExtent=\"0 1 0 1 0 1\" Origin=\"0 0 0\" Spacing=\"1 1 1\" "
    "Direction=\"1 0 0 0 1 0 0 0 1\">\n<Piece Extent=\"0 1 0 1 0 1\">\n"
    "<PointData Tensors=\"tensors\">\n<DataArray type=\"Float64\" "
    "Name=\"tensors\" NumberOfComponents=\"6\" format=\"";
  const std::string tail = "\n</DataArray>\n</PointData>\n<CellData>\n"
                           "</CellData>\n</Piece>\n</ImageData>\n</VTKFile>\n";
  std::string       ascii;
  for (unsigned int v = 0; v < 8; ++v)
    ascii += "2 2 0.5 1 0 0\n";
  const std::string binary =
    "gAEAAAAAAAA="
    "AAAAAAAAAEAAAAAAAAAAQAAAAAAAAOA/AAAAAAAA8D8AAAAAAAAAAAAAAAAAAAAA"
    "AAAAAAAAAEAAAAAAAAAAQAAAAAAAAOA/AAAAAAAA8D8AAAAAAAAAAAAAAAAAAAAA"
    "AAAAAAAAAEAAAAAAAAAAQAAAAAAAAOA/AAAAAAAA8D8AAAAAAAAAAAAAAAAAAAAA"
    "AAAAAAAAAEAAAAAAAAAAQAAAAAAAAOA/AAAAAAAA8D8AAAAAAAAAAAAAAAAAAAAA"
    "AAAAAAAAAEAAAAAAAAAAQAAAAAAAAOA/AAAAAAAA8D8AAAAAAAAAAAAAAAAAAAAA"
    "AAAAAAAAAEAAAAAAAAAAQAAAAAAAAOA/AAAAAAAA8D8AAAAAAAAAAAAAAAAAAAAA"
    "AAAAAAAAAEAAAAAAAAAAQAAAAAAAAOA/AAAAAAAA8D8AAAAAAAAAAAAAAAAAAAAA"
    "AAAAAAAAAEAAAAAAAAAAQAAAAAAAAOA/AAAAAAAA8D8AAAAAAAAAAAAAAAAAAAAA";
  const bool        use_binary = GENERATE(true, false);
  const ScratchFile file(use_binary ? "script_binary.vti" : "script_ascii.vti");
  std::ofstream(file.name) << head
                           << (use_binary ? "binary\">\n" : "ascii\">\n")
                           << (use_binary ? binary : ascii) << tail;
  const Fibres::DTIField field(parameters_for(file.name));
  const auto             sample = field.sample(Point<3>(0.3, 0.6, 0.9));
  REQUIRE(sample.status == Fibres::DTIStatus::valid);
  CHECK((sample.basis.f - unit(1, 1, 0)).norm() < 1e-12);
  CHECK((sample.basis.s - unit(-1, 1, 0)).norm() < 1e-12);
  CHECK((sample.basis.n - unit(0, 0, 1)).norm() < 1e-12);
}

TEST_CASE("DTI parameters: relative file, transform, checks", "[dti]")
{
  dealii::ParameterHandler prm;
  Fibres::DTIParameters::declare(prm);
  SECTION("defaults")
  {
    const auto p = Fibres::DTIParameters::parse(prm, "/some/folder");
    CHECK(p.file.empty());
    CHECK(p.tensor_array == "tensors");
    CHECK(p.image_to_mesh[0] == 1.0);
    CHECK(p.image_to_mesh[3] == 0.0);
    CHECK(p.minimum_fractional_anisotropy == 0.05);
    CHECK(p.maximum_rejected_fraction == 0.05);
  }
  SECTION("values")
  {
    prm.parse_input_from_string(
      "subsection Fibres\n subsection DTI\n"
      "  set File = data/heart.vti\n"
      "  set Tensor array name = DT\n"
      "  set Image to mesh transform = 0, -1, 0, 5, 1, 0, 0, 6, 0, 0, 10, 7\n"
      "  set Minimum fractional anisotropy = 0.1\n"
      " end\nend\n");
    const auto p = Fibres::DTIParameters::parse(prm, "/some/folder");
    CHECK(p.file == "/some/folder/data/heart.vti");
    CHECK(p.tensor_array == "DT");
    CHECK(p.image_to_mesh[1] == -1.0);
    CHECK(p.image_to_mesh[11] == 7.0);
    CHECK(p.minimum_fractional_anisotropy == 0.1);
  }
  SECTION("singular transform")
  {
    prm.parse_input_from_string(
      "subsection Fibres\n subsection DTI\n"
      "  set Image to mesh transform = 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0\n"
      " end\nend\n");
    CHECK_THAT(error_of([&] { Fibres::DTIParameters::parse(prm, ""); }),
               Catch::Contains("singular"));
  }
}

TEST_CASE("Round trip through the dti generator: analytic helix -> tensor "
          "image -> fibres at the quadrature points of the Land ventricle",
          "[dti]")
{
  const Geometry::LVShape     shape; // Land ventricle
  const Fibres::AnalyticHelix helix(shape,
                                    60 * degree,
                                    -60 * degree,
                                    20 * degree);
  const double                sigma = GENERATE(0.0, 0.05);
  const ScratchFile file("land_" + std::to_string(int(100 * sigma)) + ".vti");
  write_land_image(file.name, helix, shape, 0.5, sigma);

  const RoundTrip    result = land_round_trip(file.name, helix);
  const ErrorSummary fibre  = summarize(result.fibre_errors);
  const ErrorSummary sheet  = summarize(result.sheet_errors);
  std::cout << "dti round trip (0.5 mm voxels, log noise " << sigma
            << "): fibre angle error mean " << fibre.mean << ", max "
            << fibre.max << " degrees, " << 100 * fibre.fraction_below_2
            << " % within 2 degrees; sheet mean " << sheet.mean << ", max "
            << sheet.max << " degrees (" << result.fibre_errors.size()
            << " points)\n";
  INFO(result.report);
  CHECK_THAT(result.report, Catch::Contains("0 outside the data, 0 nearly"));
  if (sigma == 0.0)
    {
      CHECK(fibre.fraction_below_2 >= 0.95);
      CHECK(fibre.mean < 1.0);
      CHECK(sheet.fraction_below_2 >= 0.95);
    }
  else
    {
      // One voxel's angle error is about the off-diagonal noise over the log
      // eigenvalue gap: (sigma / sqrt 2) / log(1 / 0.7) = 0.1 rad = 5.7
      // degrees; the stencil averages some of it out.
      CHECK(fibre.mean < 5.0);
      CHECK(sheet.mean < 5.0);
    }
}

TEST_CASE("Mapping time of the dti field per million points", "[.][dti-bench]")
{
  const Geometry::LVShape     shape;
  const Fibres::AnalyticHelix helix(shape, 60 * degree, -60 * degree, 0.0);
  const ScratchFile           file("land_bench.vti");
  write_land_image(file.name, helix, shape, 0.5, 0.0);
  const auto             start = std::chrono::steady_clock::now();
  const Fibres::DTIField field(parameters_for(file.name));
  const auto             read = std::chrono::steady_clock::now();

  // 10^6 points in the wall (every query interpolates), then 10^6 points in
  // the box around it (about half take the fallback: a second eigen solve).
  std::mt19937                           rng(42);
  std::uniform_real_distribution<double> unit_interval(0, 1);
  std::vector<Point<3>>                  wall(1000000), box(1000000);
  for (auto &p : wall)
    {
      const double t     = unit_interval(rng);
      const double theta = shape.base_angle(t) * unit_interval(rng);
      const double v     = 2 * M_PI * unit_interval(rng);
      const double rs = shape.short_radius(t), rl = shape.long_radius(t);
      p = Point<3>(rs * std::sin(theta) * std::cos(v),
                   rs * std::sin(theta) * std::sin(v),
                   -rl * std::cos(theta));
    }
  for (auto &p : box)
    p = Point<3>(20 * unit_interval(rng) - 10,
                 20 * unit_interval(rng) - 10,
                 25 * unit_interval(rng) - 20);
  for (const auto *points : {&wall, &box})
    {
      double                checksum = 0.0;
      Fibres::DTIStatistics statistics;
      const std::clock_t    cpu_begin = std::clock();
      const auto            begin     = std::chrono::steady_clock::now();
      for (const auto &p : *points)
        {
          const auto sample = field.sample(p);
          checksum += sample.basis.f[2];
          statistics.add(sample.status);
        }
      const auto   end = std::chrono::steady_clock::now();
      const double cpu = double(std::clock() - cpu_begin) / CLOCKS_PER_SEC;
      std::cout << "dti: 10^6 queries "
                << (points == &wall ? "in the wall" : "in the box") << " took "
                << std::chrono::duration<double>(end - begin).count()
                << " s wall, " << cpu << " s CPU ("
                << 100 * statistics.rejected_fraction()
                << " % rejected; checksum " << checksum << ")\n";
      CHECK(std::isfinite(checksum));
    }
  std::cout << "dti: reading " << field.n_voxels()[0] << " x "
            << field.n_voxels()[1] << " x " << field.n_voxels()[2]
            << " voxels and precomputing the logs took "
            << std::chrono::duration<double>(read - start).count() << " s\n";
}

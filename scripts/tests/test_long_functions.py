"""Tests of scripts/long_functions.py: the brace scan on hand-written C++ with known lengths."""

import subprocess
import sys

from conftest import SCRIPTS_DIR

import long_functions

SOURCE = r'''
#include "x.h"
namespace systole
{
  namespace
  {
    /// A comment with a brace { that must not count.
    int
    short_one(const int a)
    {
      const char *text = "a string with } and {";
      return a + '}';
    }
  } // namespace

  struct Holder
  {
    Holder(const int a)
      : value{a}
      , other(2)
    {
      value += 1;
    }

    int value, other;
  };

  const auto table = std::vector<int>{1, 2, 3};

  template <int dim>
  double
  Holder::long_one(const double x) const
  {
    const auto f = [&](const double y) {
      return y * x;
    };
    // 1
    // 2
    // 3
    return f(x);
  }
}
'''


def test_finds_every_function_with_its_first_and_last_line():
    found = {name: (first, last) for first, last, name in long_functions.scan(SOURCE)}
    lines = SOURCE.splitlines()
    assert set(found) == {"short_one", "Holder", "Holder::long_one"}
    first, last = found["short_one"]
    assert lines[first - 1].strip() == "int" and lines[last - 1].strip() == "}"
    assert last - first + 1 == 6
    # The constructor: from its name to its body's brace, the initializer braces inside.
    first, last = found["Holder"]
    assert lines[first - 1].strip() == "Holder(const int a)"
    assert last - first + 1 == 6
    # The template line belongs to the function; the lambda inside does not split it.
    first, last = found["Holder::long_one"]
    assert lines[first - 1].strip() == "template <int dim>"
    assert last - first + 1 == 12


def test_the_command_lists_the_functions_over_the_limit(tmp_path):
    (tmp_path / "a.cc").write_text(SOURCE)
    out = subprocess.run([sys.executable, str(SCRIPTS_DIR / "long_functions.py"),
                          "--max-lines", "10", str(tmp_path)],
                         capture_output=True, text=True, check=True).stdout
    assert "Holder::long_one" in out and "short_one" not in out
    assert "1 of 3 functions are longer than 10 lines" in out


MEMBERS = r'''
namespace systole::Mechanics
{
  struct Problem::Impl
  {
  public:
    Impl(const int a) : n{a} {}
    static constexpr double tolerance = 1e-9; // static: not a member
    using Map = std::map<int, double>;
    double a = 0.0, b{1.0};                 // two
    std::map<int, std::vector<double>> table; // a comma inside <>: one
    std::function<void(int, int)> callback;   // a ( inside <>: one
    int n;
    void
    f(const int x) const;
    Impl &operator=(const Impl &) = delete;
    struct Inner
    {
      int x, y;
    } inner;                                  // one, Inner counted on its own
    enum class Kind { a, b } kind = Kind::a;  // one
  private:
    mutable std::vector<int> cache;
    double g() const { return a; }
  };
  class Empty;
}
'''


def test_counts_the_non_static_data_members_of_each_class():
    found = {name: n for _, name, n in long_functions.classes(MEMBERS)}
    assert found == {"systole::Mechanics::Problem::Impl": 8,
                     "systole::Mechanics::Problem::Impl::Inner": 2}


def test_the_command_lists_the_classes_over_the_member_limit(tmp_path):
    (tmp_path / "a.h").write_text(MEMBERS)
    out = subprocess.run([sys.executable, str(SCRIPTS_DIR / "long_functions.py"),
                          "--members", "5", str(tmp_path)],
                         capture_output=True, text=True, check=True).stdout
    assert "Problem::Impl" in out and "Inner" not in out
    assert "1 of 2 classes have more than 5 data members" in out

// the compiled N_Vector / dense SUNMatrix kernels (src/dynamics/cvode_fast_ops.cpp) against
// SUNDIALS' own serial and dense implementations on random data
#include <catch2/catch.hpp>

#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "dynamics/cvode_support.hpp"  // private to src/dynamics (tests/CMakeLists.txt adds src/)
#include "support/compare.hpp"

using namespace camopt::dynamics;

namespace {

constexpr int kLength = 23;
using camopt::test::tol::kReorderedSumRel;  // relative: reductions summed in another order

struct Context {
  SUNContext ctx = nullptr;
  Context() { REQUIRE(SUNContext_Create(nullptr, &ctx) == 0); }
  ~Context() { SUNContext_Free(&ctx); }
};

struct Vector {
  N_Vector v;
  Vector(SUNContext ctx, bool fast) : v(N_VNew_Serial(kLength, ctx)) {
    if (fast) detail::use_fast_ops(v);
  }
  ~Vector() { N_VDestroy(v); }
  double& operator[](int i) { return NV_Ith_S(v, i); }
};

// a stock and a fast vector holding the same values
struct Pair {
  Vector stock, fast;
  Pair(SUNContext ctx, std::mt19937& rng, double zero_share = 0.0) : stock(ctx, false), fast(ctx, true) {
    std::uniform_real_distribution<double> u(-2.0, 2.0), share(0.0, 1.0);
    for (int i = 0; i < kLength; ++i) stock[i] = fast[i] = share(rng) < zero_share ? 0.0 : u(rng);
  }
};

void require_same(Pair& p) {
  for (int i = 0; i < kLength; ++i) REQUIRE_REL(p.fast[i], p.stock[i], kReorderedSumRel);
}

}  // namespace

TEST_CASE("fast N_Vector ops equal the stock serial ones") {
  Context c;
  std::mt19937 rng(7);
  Pair x(c.ctx, rng), y(c.ctx, rng), w(c.ctx, rng), z(c.ctx, rng), mask(c.ctx, rng), zeros(c.ctx, rng, 0.3);
  Vector fast_clone_source(c.ctx, true);
  {  // clones keep the fast table
    N_Vector clone = N_VClone(fast_clone_source.v);
    CHECK(clone->ops->nvlinearsum == fast_clone_source.v->ops->nvlinearsum);
    CHECK(clone->ops->nvlinearsum != x.stock.v->ops->nvlinearsum);
    N_VDestroy(clone);
  }
  auto both = [&](auto op) {
    op(x.stock.v, y.stock.v, z.stock.v);
    op(x.fast.v, y.fast.v, z.fast.v);
    require_same(z);
  };
  both([](N_Vector a, N_Vector b, N_Vector r) { N_VLinearSum(0.3, a, -1.7, b, r); });
  both([](N_Vector a, N_Vector b, N_Vector) { N_VLinearSum(1.0, a, 1.0, b, b); });  // in place
  both([](N_Vector, N_Vector, N_Vector r) { N_VConst(2.5, r); });
  both([](N_Vector a, N_Vector b, N_Vector r) { N_VProd(a, b, r); });
  both([](N_Vector a, N_Vector b, N_Vector r) { N_VDiv(a, b, r); });
  both([](N_Vector a, N_Vector, N_Vector r) { N_VScale(-0.4, a, r); });
  both([](N_Vector a, N_Vector, N_Vector r) { N_VAbs(a, r); });
  both([](N_Vector a, N_Vector, N_Vector r) { N_VInv(a, r); });
  both([](N_Vector a, N_Vector, N_Vector r) { N_VAddConst(a, 0.9, r); });
  both([](N_Vector a, N_Vector, N_Vector r) { N_VCompare(1.0, a, r); });
  require_same(y);  // y was updated in place above
  for (int i = 0; i < kLength; ++i) w.stock[i] = w.fast[i] = std::abs(w.stock[i]) + 0.1;  // weights > 0
  CHECK_REL(N_VDotProd(x.fast.v, y.fast.v), N_VDotProd(x.stock.v, y.stock.v), kReorderedSumRel);
  CHECK(N_VMaxNorm(x.fast.v) == N_VMaxNorm(x.stock.v));
  CHECK_REL(N_VWrmsNorm(x.fast.v, w.fast.v), N_VWrmsNorm(x.stock.v, w.stock.v), kReorderedSumRel);
  CHECK_REL(N_VWrmsNormMask(x.fast.v, w.fast.v, mask.fast.v), N_VWrmsNormMask(x.stock.v, w.stock.v, mask.stock.v),
            kReorderedSumRel);
  CHECK(N_VMin(x.fast.v) == N_VMin(x.stock.v));
  CHECK_REL(N_VWL2Norm(x.fast.v, w.fast.v), N_VWL2Norm(x.stock.v, w.stock.v), kReorderedSumRel);
  CHECK_REL(N_VL1Norm(x.fast.v), N_VL1Norm(x.stock.v), kReorderedSumRel);
  CHECK(N_VMinQuotient(x.fast.v, zeros.fast.v) == N_VMinQuotient(x.stock.v, zeros.stock.v));
  CHECK_REL(N_VWSqrSumLocal(x.fast.v, w.fast.v), N_VWSqrSumLocal(x.stock.v, w.stock.v), kReorderedSumRel);
  {  // a zero entry: the test fails, the other entries are inverted
    const auto stock_ok = N_VInvTest(zeros.stock.v, z.stock.v);
    const auto fast_ok = N_VInvTest(zeros.fast.v, z.fast.v);
    CHECK(stock_ok == SUNFALSE);
    CHECK(fast_ok == stock_ok);
    require_same(z);
    CHECK(N_VInvTest(w.fast.v, z.fast.v) == SUNTRUE);
  }
  {  // constraints 2, 1, 0, -1, -2 on values around zero
    Pair cons(c.ctx, rng);
    for (int i = 0; i < kLength; ++i) {
      cons.stock[i] = cons.fast[i] = static_cast<double>(i % 5 - 2);
      x.stock[i] = x.fast[i] = static_cast<double>((i / 5) % 3 - 1);  // -1, 0, 1
    }
    const auto stock_ok = N_VConstrMask(cons.stock.v, x.stock.v, z.stock.v);
    CHECK(N_VConstrMask(cons.fast.v, x.fast.v, z.fast.v) == stock_ok);
    CHECK(stock_ok == SUNFALSE);
    require_same(z);
  }
  {  // fused: z = sum c_j X_j (z aliasing X_0), Z_j = a_j x + Y_j, dot products
    double coefficients[3] = {0.5, -1.25, 2.0};
    N_Vector stock_set[3] = {z.stock.v, x.stock.v, y.stock.v}, fast_set[3] = {z.fast.v, x.fast.v, y.fast.v};
    REQUIRE(N_VLinearCombination(3, coefficients, stock_set, z.stock.v) == 0);
    REQUIRE(N_VLinearCombination(3, coefficients, fast_set, z.fast.v) == 0);
    require_same(z);
    N_Vector stock_y[2] = {y.stock.v, w.stock.v}, fast_y[2] = {y.fast.v, w.fast.v};
    N_Vector stock_z[2] = {z.stock.v, w.stock.v}, fast_z[2] = {z.fast.v, w.fast.v};
    REQUIRE(N_VScaleAddMulti(2, coefficients, x.stock.v, stock_y, stock_z) == 0);
    REQUIRE(N_VScaleAddMulti(2, coefficients, x.fast.v, fast_y, fast_z) == 0);
    require_same(z);
    require_same(w);
    double stock_dots[2], fast_dots[2];
    REQUIRE(N_VDotProdMulti(2, x.stock.v, stock_y, stock_dots) == 0);
    REQUIRE(N_VDotProdMulti(2, x.fast.v, fast_y, fast_dots) == 0);
    for (int j = 0; j < 2; ++j) CHECK_REL(fast_dots[j], stock_dots[j], kReorderedSumRel);
  }
}

TEST_CASE("fast dense SUNMatrix ops equal the stock dense ones") {
  Context c;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  constexpr int n = 7;
  SUNMatrix stock = SUNDenseMatrix(n, n, c.ctx), fast = SUNDenseMatrix(n, n, c.ctx);
  detail::use_fast_ops(fast);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) SM_ELEMENT_D(stock, i, j) = SM_ELEMENT_D(fast, i, j) = u(rng);
  SUNMatrix stock_copy = SUNMatClone(stock), fast_copy = SUNMatClone(fast);
  CHECK(fast_copy->ops->copy == fast->ops->copy);  // clones keep the fast table
  REQUIRE(SUNMatCopy(stock, stock_copy) == 0);
  REQUIRE(SUNMatCopy(fast, fast_copy) == 0);
  REQUIRE(SUNMatScaleAddI(-0.37, stock_copy) == 0);
  REQUIRE(SUNMatScaleAddI(-0.37, fast_copy) == 0);
  REQUIRE(SUNMatScaleAdd(2.5, stock, stock_copy) == 0);
  REQUIRE(SUNMatScaleAdd(2.5, fast, fast_copy) == 0);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      CHECK_REL(SM_ELEMENT_D(fast_copy, i, j), SM_ELEMENT_D(stock_copy, i, j), kReorderedSumRel);
      CHECK_REL(SM_ELEMENT_D(fast, i, j), SM_ELEMENT_D(stock, i, j), kReorderedSumRel);
    }
  REQUIRE(SUNMatZero(fast_copy) == 0);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) CHECK(SM_ELEMENT_D(fast_copy, i, j) == 0.0);
  for (SUNMatrix m : {stock, fast, stock_copy, fast_copy}) SUNMatDestroy(m);
}

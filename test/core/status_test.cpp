// SPDX-License-Identifier: MIT
// Status, Result<T> and DG_RETURN_IF_ERROR.
#include <gtest/gtest.h>

#include <memory>
#include <set>
#include <string>

#include "dualgraph/core/status.h"

namespace dualgraph {
namespace {

TEST(Status, DefaultIsOkAndPrintsOk) {
  const Status status;
  EXPECT_TRUE(status.ok());
  EXPECT_EQ(status.code(), StatusCode::kOk);
  EXPECT_EQ(status.message(), "");
  EXPECT_EQ(status.toString(), "OK");
  EXPECT_TRUE(Status::okStatus().ok());
}

TEST(Status, ErrorCarriesCodeAndMessage) {
  const Status status(StatusCode::kParseError, "file.g2o:12: bad field");
  EXPECT_FALSE(status.ok());
  EXPECT_EQ(status.code(), StatusCode::kParseError);
  EXPECT_EQ(status.message(), "file.g2o:12: bad field");
  EXPECT_EQ(status.toString(), "ParseError: file.g2o:12: bad field");
}

TEST(Status, EveryCodeHasADistinctName) {
  const StatusCode codes[] = {StatusCode::kOk,          StatusCode::kInvalidArgument,
                              StatusCode::kParseError,  StatusCode::kNotFound,
                              StatusCode::kAlreadyExists, StatusCode::kIoError,
                              StatusCode::kNotPositiveDefinite, StatusCode::kNumericalError,
                              StatusCode::kFailedPrecondition};
  std::set<std::string> names;
  for (StatusCode code : codes) {
    const std::string name = statusCodeName(code);
    EXPECT_NE(name, "Unknown");
    names.insert(name);
  }
  EXPECT_EQ(names.size(), std::size(codes));
  EXPECT_STREQ(statusCodeName(StatusCode::kNotPositiveDefinite), "NotPositiveDefinite");
}

TEST(Result, HoldsAValueAccessibleThroughEveryAccessor) {
  Result<std::string> result(std::string("abc"));
  ASSERT_TRUE(result.ok());
  EXPECT_TRUE(result.status().ok());
  EXPECT_EQ(result.value(), "abc");
  EXPECT_EQ(*result, "abc");
  EXPECT_EQ(result->size(), 3u);
  const Result<std::string>& as_const = result;
  EXPECT_EQ(as_const.value(), "abc");
  const std::string moved = std::move(result).value();
  EXPECT_EQ(moved, "abc");
}

TEST(Result, HoldsAMoveOnlyValue) {
  Result<std::unique_ptr<int>> result(std::make_unique<int>(7));
  ASSERT_TRUE(result.ok());
  std::unique_ptr<int> owned = *std::move(result);
  ASSERT_NE(owned, nullptr);
  EXPECT_EQ(*owned, 7);
}

TEST(Result, ValueOnAnErrorThrowsContractViolationNamingTheStatus) {
  Result<int> result(Status(StatusCode::kNotFound, "vertex 3"));
  EXPECT_FALSE(result.ok());
  EXPECT_EQ(result.status().code(), StatusCode::kNotFound);
  EXPECT_THROW(result.value(), ContractViolation);
  EXPECT_THROW(*result, ContractViolation);
  EXPECT_THROW(std::move(result).value(), ContractViolation);
  Result<std::string> text(Status(StatusCode::kIoError, "disk"));
  EXPECT_THROW((void)text->size(), ContractViolation);
  try {
    (void)result.value();
    FAIL() << "no exception";
  } catch (const ContractViolation& e) {
    EXPECT_NE(std::string(e.what()).find("NotFound: vertex 3"), std::string::npos) << e.what();
  }
}

TEST(Result, ConstructingFromAnOkStatusIsAContractViolation) {
  EXPECT_THROW((void)Result<int>{Status()}, ContractViolation);
}

TEST(Result, ContractViolationIsALogicError) {
  try {
    Result<int> result(Status(StatusCode::kInvalidArgument, "x"));
    (void)result.value();
  } catch (const std::logic_error&) {
    SUCCEED();
    return;
  }
  FAIL() << "ContractViolation is not a std::logic_error";
}

Status step(int& calls, Status outcome) {
  ++calls;
  return outcome;
}

Status twoSteps(int& calls, Status first, Status second) {
  DG_RETURN_IF_ERROR(step(calls, first));
  DG_RETURN_IF_ERROR(step(calls, second));
  return Status();
}

TEST(DgReturnIfError, ContinuesOnOkAndReturnsTheFirstError) {
  int calls = 0;
  EXPECT_TRUE(twoSteps(calls, Status(), Status()).ok());
  EXPECT_EQ(calls, 2);

  calls = 0;
  const Status first = twoSteps(calls, Status(StatusCode::kParseError, "first"), Status(StatusCode::kIoError, "second"));
  EXPECT_EQ(calls, 1) << "the second expression must not be evaluated";
  EXPECT_EQ(first.code(), StatusCode::kParseError);
  EXPECT_EQ(first.message(), "first");

  calls = 0;
  const Status second = twoSteps(calls, Status(), Status(StatusCode::kIoError, "second"));
  EXPECT_EQ(calls, 2);
  EXPECT_EQ(second.code(), StatusCode::kIoError);
}

}  // namespace
}  // namespace dualgraph

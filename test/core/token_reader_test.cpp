// SPDX-License-Identifier: MIT
// TokenReader: strict numbers, error messages naming source:line and field, trailing garbage.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <string>

#include "dualgraph/core/token_reader.h"
#include "test/core/test_fixtures.h"

namespace dualgraph {
namespace {

using testing::contains;

TEST(TokenReader, ReadsTokensIntsAndDoublesSeparatedByAnyWhitespace) {
  TokenReader in("TAG\t-12  3.5e-1 \r 42 -0.0\v7\f1e300\n", "a.g2o", 3);
  std::string tag;
  int i = 0;
  int j = 0;
  double x = 0.0;
  double y = 1.0;
  double z = 0.0;
  double w = 0.0;
  EXPECT_EQ(in.remaining(), 7u);
  ASSERT_TRUE(in.readToken(tag, "tag").ok());
  ASSERT_TRUE(in.readInt(i, "i").ok());
  ASSERT_TRUE(in.readDouble(x, "x").ok());
  ASSERT_TRUE(in.readInt(j, "j").ok());
  ASSERT_TRUE(in.readDouble(y, "y").ok());
  ASSERT_TRUE(in.readDouble(z, "z").ok());
  ASSERT_TRUE(in.readDouble(w, "w").ok());
  EXPECT_EQ(tag, "TAG");
  EXPECT_EQ(i, -12);
  EXPECT_EQ(x, 0.35);
  EXPECT_EQ(j, 42);
  EXPECT_EQ(y, 0.0);
  EXPECT_EQ(z, 7.0);
  EXPECT_EQ(w, 1e300);
  EXPECT_TRUE(in.atEnd());
  EXPECT_TRUE(in.finish().ok());
  EXPECT_EQ(in.location(), "a.g2o:3");
  EXPECT_EQ(in.source(), "a.g2o");
  EXPECT_EQ(in.lineNumber(), 3);
}

TEST(TokenReader, IntegersAtTheLimitsOfIntAreRead) {
  TokenReader in("2147483647 -2147483648 +5", "<string>", 1);
  int a = 0;
  int b = 0;
  int c = 0;
  ASSERT_TRUE(in.readInt(a, "a").ok());
  ASSERT_TRUE(in.readInt(b, "b").ok());
  ASSERT_TRUE(in.readInt(c, "c").ok());
  EXPECT_EQ(a, 2147483647);
  EXPECT_EQ(b, -2147483647 - 1);
  EXPECT_EQ(c, 5);
}

TEST(TokenReader, UnderflowIsReadAsATinyFiniteNumber) {
  // Only overflow is an error: a denormal or zero is a faithful reading of "1e-400".
  TokenReader in("1e-400", "<string>", 1);
  double x = 1.0;
  ASSERT_TRUE(in.readDouble(x, "x").ok());
  EXPECT_TRUE(std::isfinite(x));
  EXPECT_LT(std::fabs(x), 1e-300);
}

class TokenReaderRejectsDouble : public ::testing::TestWithParam<const char*> {};

TEST_P(TokenReaderRejectsDouble, WithAParseErrorNamingLocationFieldAndToken) {
  const std::string token = GetParam();
  TokenReader in(token + " 5", "test.g2o", 7);
  double value = 123.0;
  const Status status = in.readDouble(value, "x");
  ASSERT_FALSE(status.ok()) << "accepted '" << token << "' as " << value;
  EXPECT_EQ(status.code(), StatusCode::kParseError);
  EXPECT_TRUE(contains(status.message(), "test.g2o:7: "));
  EXPECT_TRUE(contains(status.message(), "field 'x'"));
  EXPECT_TRUE(contains(status.message(), "'" + token + "'"));
}

INSTANTIATE_TEST_SUITE_P(NonFiniteOrPartial, TokenReaderRejectsDouble,
                         ::testing::Values("nan", "NaN", "-nan", "inf", "-inf", "+inf", "infinity",
                                           "1e400", "-1e400", "1.5x", "abc", "1,5", "0x", "--1",
                                           "1e", "."));

TEST(TokenReader, EmptyLineReportsTheMissingField) {
  TokenReader in("", "test.g2o", 4);
  double value = 0.0;
  const Status status = in.readDouble(value, "range");
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.code(), StatusCode::kParseError);
  EXPECT_EQ(status.message(), "test.g2o:4: line ends before field 'range'");
}

TEST(TokenReader, ReadIntRejectsFractionsOverflowAndGarbage) {
  for (const char* token : {"1.5", "1e3", "2147483648", "-2147483649", "99999999999999999999", "12abc",
                            "x", "nan", "0x10"}) {
    TokenReader in(token, "ints.txt", 9);
    int value = -7;
    const Status status = in.readInt(value, "id");
    ASSERT_FALSE(status.ok()) << "accepted '" << token << "' as " << value;
    EXPECT_EQ(status.code(), StatusCode::kParseError);
    EXPECT_TRUE(contains(status.message(), "ints.txt:9: field 'id'"));
    EXPECT_TRUE(contains(status.message(), std::string("'") + token + "'"));
  }
}

TEST(TokenReader, MissingFieldMessageNamesTheFieldAndFileLine) {
  TokenReader in("EDGE 1", "graph.g2o", 12);
  std::string tag;
  int id = 0;
  int second = 0;
  ASSERT_TRUE(in.readToken(tag, "tag").ok());
  ASSERT_TRUE(in.readInt(id, "vertex id 1").ok());
  for (const Status& status : {in.readInt(second, "vertex id 2"), in.readToken(tag, "vertex id 2")}) {
    ASSERT_FALSE(status.ok());
    EXPECT_EQ(status.code(), StatusCode::kParseError);
    EXPECT_EQ(status.message(), "graph.g2o:12: line ends before field 'vertex id 2'");
  }
}

TEST(TokenReader, FinishReportsTrailingGarbage) {
  TokenReader in("1 2 junk more", "t.g2o", 5);
  int a = 0;
  ASSERT_TRUE(in.readInt(a, "a").ok());
  ASSERT_TRUE(in.readInt(a, "b").ok());
  const Status status = in.finish();
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.code(), StatusCode::kParseError);
  EXPECT_TRUE(contains(status.message(), "t.g2o:5: "));
  EXPECT_TRUE(contains(status.message(), "2 unexpected trailing field(s)"));
  EXPECT_TRUE(contains(status.message(), "'junk'"));
}

TEST(TokenReader, ReadVectorNamesTheIndexedFieldOnError) {
  TokenReader in("1 2 oops", "v.g2o", 2);
  Eigen::Vector3d v;
  const Status status = in.readVector<3>(v, "xyz");
  ASSERT_FALSE(status.ok());
  EXPECT_TRUE(contains(status.message(), "v.g2o:2: field 'xyz[2]'"));

  TokenReader short_line("1 2", "v.g2o", 3);
  const Status missing = short_line.readVector<3>(v, "xyz");
  EXPECT_TRUE(contains(missing.message(), "v.g2o:3: line ends before field 'xyz[2]'"));
}

TEST(TokenReader, ReadUpperTriangleMirrorsIntoTheLowerTriangle) {
  TokenReader in("1 2 3 4 5 6", "<string>", 1);
  Eigen::Matrix3d m;
  m.setConstant(-1.0);
  ASSERT_TRUE(in.readUpperTriangle<3>(m, "information").ok());
  Eigen::Matrix3d expected;
  expected << 1, 2, 3,
              2, 4, 5,
              3, 5, 6;
  EXPECT_EQ(m, expected);
  EXPECT_TRUE(in.finish().ok());
}

TEST(TokenReader, ReadUpperTriangleNamesTheEntryIndexOnError) {
  TokenReader in("1 2 3 4 x 6", "info.g2o", 8);
  Eigen::Matrix3d m;
  const Status status = in.readUpperTriangle<3>(m, "information");
  ASSERT_FALSE(status.ok());
  EXPECT_TRUE(contains(status.message(), "info.g2o:8: field 'information[4]'"));
}

TEST(TokenReader, ErrorBuildsAParseErrorPrefixedWithTheLocation) {
  TokenReader in("a b", "src.g2o", 42);
  const Status status = in.error("something");
  EXPECT_EQ(status.code(), StatusCode::kParseError);
  EXPECT_EQ(status.message(), "src.g2o:42: something");
}

TEST(TokenReader, QuotedEscapesNonPrintableBytesAndTruncatesLongTokens) {
  EXPECT_EQ(TokenReader::quoted("abc"), "'abc'");
  EXPECT_EQ(TokenReader::quoted(std::string("a\x01\xff", 3)), "'a\\x01\\xff'");
  EXPECT_EQ(TokenReader::quoted(std::string(40, 'x')), "'" + std::string(40, 'x') + "'");
  EXPECT_EQ(TokenReader::quoted(std::string(41, 'x')), "'" + std::string(40, 'x') + "...'");
  EXPECT_EQ(TokenReader::indexedField("xy", 3), "xy[3]");
}

TEST(TokenReader, CopiesTheLineSoATemporaryMayBePassed) {
  auto make = [] { return std::string("  17   2.5  "); };
  TokenReader in(make(), "<string>", 1);  // the temporary dies here; tokens must point into a copy
  std::string scribble(64, 'z');          // likely reuses the freed storage
  int a = 0;
  double b = 0.0;
  ASSERT_TRUE(in.readInt(a, "a").ok());
  ASSERT_TRUE(in.readDouble(b, "b").ok());
  EXPECT_EQ(a, 17);
  EXPECT_EQ(b, 2.5);
  EXPECT_TRUE(in.finish().ok());
}

}  // namespace
}  // namespace dualgraph

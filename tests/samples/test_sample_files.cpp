// Sample files (validate/samples/sample_file.h, sample_arrays.h): .npy and raw
// float32 read as NumPy and a GPU kernel write them, and refused with a message
// that says what was expected.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "support/temp_dir.h"
#include "validate/samples/sample_arrays.h"
#include "validate/samples/sample_file.h"

namespace warpcheck {
namespace {

std::string npy(const std::string& descr, const std::string& shape, const std::string& data, bool fortran = false) {
    std::string header = "{'descr': '" + descr + "', 'fortran_order': " + (fortran ? "True" : "False") +
                         ", 'shape': " + shape + ", }";
    header.append(64 - (10 + header.size() + 1) % 64, ' ');
    header.push_back('\n');
    std::string out("\x93NUMPY\x01\x00", 8);
    out.push_back(static_cast<char>(header.size() & 0xff));
    out.push_back(static_cast<char>(header.size() >> 8));
    return out + header + data;
}

std::string le32(float v) {
    const auto w = std::bit_cast<uint32_t>(v);
    return {static_cast<char>(w), static_cast<char>(w >> 8), static_cast<char>(w >> 16), static_cast<char>(w >> 24)};
}

TEST(SampleFiles, NpyWrittenAndReadBackExactly) {
    NumericArray a;
    a.type = ElementType::Float32;
    a.rows = 3;
    a.cols = 2;
    a.reals = {0.0, 0x1p-149, 1.0 - 0x1p-24, -0.5, std::nan(""), 3.25};
    const NumericArray b = parse_npy(npy_bytes(a), "a.npy");
    EXPECT_EQ(b.describe(), "float32 array of shape (3, 2)");
    ASSERT_EQ(b.reals.size(), 6u);
    for (std::size_t i = 0; i < 6; ++i)
        EXPECT_TRUE(b.reals[i] == a.reals[i] || (std::isnan(b.reals[i]) && std::isnan(a.reals[i]))) << i;
    NumericArray bits;
    bits.type = ElementType::UInt64;
    bits.rows = 2;
    bits.one_dimensional = true;
    bits.integers = {UINT64_MAX, 12345};
    const NumericArray c = parse_npy(npy_bytes(bits), "b.npy");
    EXPECT_TRUE(c.one_dimensional);
    EXPECT_EQ(c.integers, bits.integers);
}

TEST(SampleFiles, FortranOrderAndBigEndianAreReadAsNumPyMeansThem) {
    // Fortran order: column by column.
    std::string data;
    for (float v : {1.0f, 2.0f, 3.0f, 4.0f}) data += le32(v);
    const NumericArray f = parse_npy(npy("<f4", "(2, 2)", data, true), "f.npy");
    EXPECT_EQ(f.reals, (std::vector<double>{1, 3, 2, 4}));
    std::string big = le32(1.5f);
    std::reverse(big.begin(), big.end());
    EXPECT_EQ(parse_npy(npy(">f4", "(1,)", big), "b.npy").reals, std::vector<double>{1.5});
}

TEST(SampleFiles, WhatIsNotSamplesIsRefusedWithWhatWasExpected) {
    const auto problem = [](const std::string& bytes) {
        try {
            (void)parse_npy(bytes, "x.npy");
        } catch (const SampleFileError& e) {
            return std::string(e.what());
        }
        return std::string("accepted");
    };
    EXPECT_NE(problem("PK\x03\x04 not numpy").find("not a NumPy .npy file"), std::string::npos);
    EXPECT_NE(problem(npy("<i4", "(1,)", "\0\0\0\0")).find("'<i4' is not supported"), std::string::npos);
    EXPECT_NE(problem(npy("<f4", "(1, 1, 1)", le32(1))).find("3 dimensions"), std::string::npos);
    EXPECT_NE(problem(npy("<f4", "(4, 3)", le32(1))).find("cut short"), std::string::npos);
}

TEST(SampleFiles, RawFloat32InEitherLayout) {
    testing::TempDir dir;
    {
        std::ofstream out(dir.file("x.f32"), std::ios::binary);
        for (float v : {1.0f, 2.0f, 3.0f, 4.0f, 5.0f, 6.0f}) out << le32(v);
    }
    const NumericArray interleaved = read_raw_float32(dir.file("x.f32"), parse_raw_layout("3"));
    EXPECT_EQ(interleaved.rows, 2u);
    EXPECT_EQ(interleaved.reals, (std::vector<double>{1, 2, 3, 4, 5, 6}));
    const NumericArray planar = read_raw_float32(dir.file("x.f32"), parse_raw_layout("3,planar"));
    EXPECT_EQ(planar.reals, (std::vector<double>{1, 3, 5, 2, 4, 6}));
    EXPECT_THROW((void)read_raw_float32(dir.file("x.f32"), parse_raw_layout("4")), SampleFileError);
    EXPECT_THROW((void)parse_raw_layout("2,diagonal"), SampleFileError);
    EXPECT_EQ(read_raw_float32(dir.file("x.f32"), {.columns = 2, .planar = false}).rows, 3u);
}

TEST(SampleArrays, InputsAndOutputsAreCheckedAgainstTheirKind) {
    NumericArray u;
    u.rows = 2;
    u.cols = 2;
    u.reals = {0.25, 0.5, 0.75, 1.0};  // 1.0 is not an input
    EXPECT_THROW((void)inputs_of(u, InputKind::Uniform2D, "u"), SampleFileError);
    u.reals[3] = 0.125;
    const std::vector<WarpInput> in = inputs_of(u, InputKind::Uniform2D, "u");
    EXPECT_EQ(in[1].u[1], 0.125f);
    EXPECT_THROW((void)inputs_of(u, InputKind::Uniform1D, "u"), SampleFileError);
    u.type = ElementType::Float64;
    EXPECT_THROW((void)inputs_of(u, InputKind::Uniform2D, "u"), SampleFileError) << "a double input is not the input";
    try {
        (void)outputs_of(u, 3, "x.npy");
        FAIL() << "a (2, 2) array is not of 3D samples";
    } catch (const SampleFileError& e) {
        EXPECT_NE(std::string(e.what()).find("shape (n, 3), not a float64 array of shape (2, 2)"), std::string::npos)
            << e.what();
    }
    std::vector<double> values;
    const std::vector<WarpOutput> x = outputs_of(u, 1, "x.npy", &values);
    EXPECT_EQ(x[1][0], 0.75f);
    EXPECT_EQ(values[1], 0.125);
}

}  // namespace
}  // namespace warpcheck

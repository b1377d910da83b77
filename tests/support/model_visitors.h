// Test visitors over the result model's descriptions (reports/result.h): fill
// every member of a value, flatten a value to (place, value) lines to compare
// two values member by member, count the members a description names, and count
// the members a type has. Made from the descriptions, so that a new member is
// filled and compared without touching a test.
#pragma once

#include <bit>
#include <cmath>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "reports/result_json.h"

namespace warpcheck::testing {

/// Sets every member to a value that differs from its default and from its
/// neighbours'. `variant` shifts the choices, so that the variants 0..3 between
/// them give every bool both values, every enum each of its values (up to four),
/// and optional numbers both null and set.
class FillVisitor {
public:
    FillVisitor(int variant, std::vector<double> doubles, std::vector<std::string> texts)
        : variant_(variant), doubles_(std::move(doubles)), texts_(std::move(texts)) {}

    template <class T>
    void operator()(const char*, T& value) {
        fill(value);
    }
    template <class Describe>
    void group(const char*, Describe&& describe) {
        describe(*this);
    }
    template <class Describe>
    void optional_group(const char*, bool, Describe&& describe) {
        describe(*this);
    }
    template <class T>
    void named_numbers(const char*, std::vector<T>& list) {
        list.resize(3);
        for (T& element : list) fields(*this, element);
    }
    void entry(std::string& name, double& value) {
        name = fmt::format("name{}", next());  // names are keys of a JSON object: distinct
        fill(value);
    }

    template <Described T>
    void fill(T& value) {
        fields(*this, value);
    }
    void fill(double& d) { d = doubles_[static_cast<std::size_t>(next()) % doubles_.size()]; }
    void fill(bool& b) { b = (next() + variant_) % 2 == 1; }
    void fill(std::string& s) { s = texts_[static_cast<std::size_t>(next()) % texts_.size()] + std::to_string(counter_); }
    template <std::integral I>
    void fill(I& i) {
        // Near the top of the type's range: a count that passes through a double loses the low bits.
        i = static_cast<I>(std::numeric_limits<I>::max() - static_cast<I>(next()));
    }
    void fill(std::optional<double>& v) {
        if ((next() + variant_) % 3 == 0) return v.reset();
        fill(v.emplace());
    }
    template <class E>
        requires std::is_enum_v<E>
    void fill(E& e) {
        e = static_cast<E>(static_cast<std::size_t>(next() + variant_) % EnumNames<E>::names.size());
    }
    template <class T>
    void fill(std::vector<T>& list) {
        list.resize(2);
        for (T& element : list) fill(element);
    }

private:
    int next() { return ++counter_; }
    int counter_ = 0;
    int variant_;
    std::vector<double> doubles_;
    std::vector<std::string> texts_;
};

/// Every value of a model value, one line per leaf: "results[1].plots[0].title = ...".
/// Doubles as their bit patterns, except that with `nan_is_nan` every NaN is one
/// (the JSON report writes "NaN", whatever the payload).
class FlattenVisitor {
public:
    FlattenVisitor(std::vector<std::string>& lines, std::string place, bool nan_is_nan)
        : lines_(lines), place_(std::move(place)), nan_is_nan_(nan_is_nan) {}

    template <class T>
    void operator()(const char* key, const T& value) {
        put(place_ + "." + key, value);
    }
    template <class Describe>
    void group(const char* key, Describe&& describe) {
        FlattenVisitor inner(lines_, place_ + "." + key, nan_is_nan_);
        describe(inner);
    }
    template <class Describe>
    void optional_group(const char* key, bool, Describe&& describe) {
        group(key, describe);
    }
    template <class T>
    void named_numbers(const char* key, const std::vector<T>& list) {
        FlattenVisitor inner(lines_, place_ + "." + key, nan_is_nan_);
        for (const T& element : list) fields(inner, element);
    }
    void entry(const std::string& name, double value) { put(place_ + "[" + name + "]", value); }

    template <Described T>
    void put(const std::string& place, const T& value) {
        FlattenVisitor inner(lines_, place, nan_is_nan_);
        fields(inner, value);
    }
    void put(const std::string& place, double d) {
        lines_.push_back(place + " = " + (nan_is_nan_ && std::isnan(d) ? "NaN" : fmt::format("{:a} (bits {:x})", d, std::bit_cast<uint64_t>(d))));
    }
    void put(const std::string& place, bool b) { lines_.push_back(place + " = " + (b ? "true" : "false")); }
    void put(const std::string& place, const std::string& s) { lines_.push_back(place + " = '" + s + "'"); }
    template <std::integral I>
    void put(const std::string& place, I i) {
        lines_.push_back(place + " = " + std::to_string(i));
    }
    void put(const std::string& place, const std::optional<double>& v) {
        if (v) return put(place, *v);
        lines_.push_back(place + " = null");
    }
    template <class E>
        requires std::is_enum_v<E>
    void put(const std::string& place, E e) {
        lines_.push_back(place + " = enumerator " + std::to_string(static_cast<std::size_t>(e)));
    }
    template <class T>
    void put(const std::string& place, const std::vector<T>& list) {
        lines_.push_back(place + " has " + std::to_string(list.size()));
        for (std::size_t i = 0; i < list.size(); ++i) put(place + "[" + std::to_string(i) + "]", list[i]);
    }

private:
    std::vector<std::string>& lines_;
    std::string place_;
    bool nan_is_nan_;
};

template <class T>
std::vector<std::string> flatten(const T& value, bool nan_is_nan) {
    std::vector<std::string> lines;
    FlattenVisitor(lines, "", nan_is_nan).put("", value);
    return lines;
}

/// How many members a description names, not counting those of nested types.
class MemberCounter {
public:
    template <class T>
    void operator()(const char*, const T&) {
        ++count;
    }
    template <class Describe>
    void group(const char*, Describe&& describe) {
        describe(*this);
    }
    template <class Describe>
    void optional_group(const char*, bool, Describe&& describe) {
        describe(*this);
    }
    template <class T>
    void named_numbers(const char*, const std::vector<T>&) {
        ++count;
    }
    void entry(const std::string&, double) { count += 2; }
    int count = 0;
};

template <class T>
int described_members() {
    MemberCounter counter;
    const T value{};
    fields(counter, value);
    return counter.count;
}

namespace detail {
/// Converts to a reference to anything: the aggregate initialiser T{any, any, ...}
/// compiles for as many of them as T has members.
struct AnyMember {
    template <class T>
    operator T&() const&&;
};
template <class T, std::size_t... I>
constexpr bool initialisable_from(std::index_sequence<I...>) {
    return requires { T{(void(I), AnyMember{})...}; };
}
}  // namespace detail

/// How many members the aggregate T has.
template <class T, std::size_t N = 0>
constexpr int aggregate_members() {
    if constexpr (detail::initialisable_from<T>(std::make_index_sequence<N + 1>{}))
        return aggregate_members<T, N + 1>();
    else
        return static_cast<int>(N);
}

}  // namespace warpcheck::testing

// The result model (reports/result.h) to and from nlohmann JSON values, made
// from the types' descriptions (their `fields` functions): nothing here names a
// member. The JSON report and the --merge reader write doubles as decimal text
// (TextNumbers); the worker codec writes their bit patterns (BitNumbers).
#pragma once

#include <bit>
#include <cmath>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "reports/result.h"

namespace warpcheck {

using ResultJson = nlohmann::ordered_json;

/// A value that is not what the model says it is; the message says where
/// (e.g. "results[3].plots[0].kind: 'pie' is not a plot kind").
struct ResultFormatError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

/// Doubles as JSON numbers, whose decimal text round-trips every finite double;
/// NaN and the infinities (JSON has none) as the strings "NaN", "Infinity" and
/// "-Infinity", so that nothing is lost (a NaN figure is often the finding).
/// Named numbers as one object, name -> number.
struct TextNumbers {
    static constexpr bool named_numbers_as_object = true;
    static ResultJson write(double v) {
        if (std::isnan(v)) return "NaN";
        if (std::isinf(v)) return v > 0 ? "Infinity" : "-Infinity";
        return v;
    }
    static std::optional<double> read(const ResultJson& j) {
        if (j.is_number()) return j.get<double>();
        if (j == "NaN") return std::numeric_limits<double>::quiet_NaN();
        if (j == "Infinity") return std::numeric_limits<double>::infinity();
        if (j == "-Infinity") return -std::numeric_limits<double>::infinity();
        return std::nullopt;
    }
};

/// Doubles as the integers of their bit patterns: exact for every double (NaN
/// payloads, infinities, -0). Named numbers as a list of [name, number] pairs,
/// so that a repeated name survives too.
struct BitNumbers {
    static constexpr bool named_numbers_as_object = false;
    static ResultJson write(double v) { return std::bit_cast<uint64_t>(v); }
    static std::optional<double> read(const ResultJson& j) {
        if (!j.is_number_unsigned()) return std::nullopt;
        return std::bit_cast<double>(j.get<uint64_t>());
    }
};

namespace result_json_detail {
/// Stands in for a visitor where only the existence of a description matters.
struct AnyVisitor {};
}  // namespace result_json_detail

/// A model type with a description (`fields`) in reports/result.h.
template <class T>
concept Described = requires(result_json_detail::AnyVisitor& v, T& value) { fields(v, value); };

/// Where a value sits in a document, e.g. results[3].plots[0].kind: a chain
/// through the enclosing values, spelled out only for an error message.
struct JsonPlace {
    const JsonPlace* parent = nullptr;
    std::string_view key;  ///< empty: element `index` of an array
    std::size_t index = 0;

    std::string str() const {
        std::string text = parent ? parent->str() : std::string();
        if (!key.empty()) return text + (text.empty() ? "" : ".") + std::string(key);
        return text + "[" + std::to_string(index) + "]";
    }
};

/// Writes model values as JSON, member by member as their descriptions say.
template <class Numbers>
class FieldWriter {
public:
    explicit FieldWriter(ResultJson& object) : out_(object) {}

    template <class T>
    void operator()(const char* key, const T& value) {
        out_[key] = write(value);
    }
    template <class Describe>
    void group(const char* key, Describe&& describe) {
        ResultJson inner = ResultJson::object();
        FieldWriter writer(inner);
        describe(writer);
        out_[key] = std::move(inner);
    }
    template <class Describe>
    void optional_group(const char* key, bool present, Describe&& describe) {
        if (present) group(key, describe);
    }
    template <class T>
    void named_numbers(const char* key, const std::vector<T>& list) {
        ResultJson all = Numbers::named_numbers_as_object ? ResultJson::object() : ResultJson::array();
        for (const T& element : list) {
            EntryWriter writer{all};
            fields(writer, element);
        }
        out_[key] = std::move(all);
    }

    static ResultJson write(double v) { return Numbers::write(v); }
    static ResultJson write(bool b) { return b; }
    static ResultJson write(const std::string& s) { return s; }
    template <std::integral I>
    static ResultJson write(I i) {
        return i;
    }
    static ResultJson write(const std::optional<double>& v) { return v ? write(*v) : ResultJson(nullptr); }
    template <class E>
        requires std::is_enum_v<E>
    static ResultJson write(E e) {
        const auto index = static_cast<std::size_t>(e);
        if (index >= EnumNames<E>::names.size()) throw ResultFormatError("an enumerator without a name");
        return std::string(EnumNames<E>::names[index]);
    }
    template <class T>
    static ResultJson write(const std::vector<T>& list) {
        ResultJson array = ResultJson::array();
        for (const T& element : list) array.push_back(write(element));
        return array;
    }
    template <Described T>
    static ResultJson write(const T& value) {
        ResultJson object = ResultJson::object();
        FieldWriter writer(object);
        fields(writer, value);
        return object;
    }

private:
    struct EntryWriter {
        ResultJson& all;
        void entry(const std::string& name, double value) {
            if constexpr (Numbers::named_numbers_as_object) all[name] = Numbers::write(value);
            else all.push_back(ResultJson::array({ResultJson(name), Numbers::write(value)}));
        }
    };
    ResultJson& out_;
};

/// Reads model values from JSON as their descriptions say; every member must be
/// there with its type (unknown members are ignored). Throws ResultFormatError.
template <class Numbers>
class FieldReader {
public:
    FieldReader(const ResultJson& object, const JsonPlace& place) : in_(object), place_(place) {}

    template <class T>
    void operator()(const char* key, T& value) {
        const JsonPlace place{&place_, key};
        read(member(place), value, place);
    }
    template <class Describe>
    void group(const char* key, Describe&& describe) {
        const JsonPlace place{&place_, key};
        FieldReader reader(object(member(place), place), place);
        describe(reader);
    }
    template <class Describe>
    void optional_group(const char* key, bool /*present*/, Describe&& describe) {
        if (in_.contains(key)) group(key, describe);
    }
    template <class T>
    void named_numbers(const char* key, std::vector<T>& list) {
        const JsonPlace place{&place_, key};
        const ResultJson& all = member(place);
        list.clear();
        if constexpr (Numbers::named_numbers_as_object) {
            for (const auto& [name, number] : object(all, place).items()) read_entry(name, number, place, list);
        } else {
            if (!all.is_array()) fail(place, "not a list");
            for (const ResultJson& pair : all) {
                if (!pair.is_array() || pair.size() != 2 || !pair[0].is_string()) fail(place, "not a list of [name, number] pairs");
                read_entry(pair[0].get<std::string>(), pair[1], place, list);
            }
        }
    }

    static void read(const ResultJson& j, double& value, const JsonPlace& place) {
        const std::optional<double> v = Numbers::read(j);
        if (!v) fail(place, "not a number");
        value = *v;
    }
    static void read(const ResultJson& j, bool& value, const JsonPlace& place) {
        if (!j.is_boolean()) fail(place, "not true or false");
        value = j.get<bool>();
    }
    static void read(const ResultJson& j, std::string& value, const JsonPlace& place) {
        if (!j.is_string()) fail(place, "not a string");
        value = j.get<std::string>();
    }
    template <std::integral I>
    static void read(const ResultJson& j, I& value, const JsonPlace& place) {
        const bool fits = j.is_number_unsigned() ? std::in_range<I>(j.get<uint64_t>())
                                                 : j.is_number_integer() && std::in_range<I>(j.get<int64_t>());
        if (!fits) fail(place, "not an integer in range");
        value = j.is_number_unsigned() ? static_cast<I>(j.get<uint64_t>()) : static_cast<I>(j.get<int64_t>());
    }
    static void read(const ResultJson& j, std::optional<double>& value, const JsonPlace& place) {
        if (j.is_null()) return value.reset();
        read(j, value.emplace(), place);
    }
    template <class E>
        requires std::is_enum_v<E>
    static void read(const ResultJson& j, E& value, const JsonPlace& place) {
        const auto& names = EnumNames<E>::names;
        for (std::size_t i = 0; i < names.size(); ++i)
            if (j.is_string() && j.get_ref<const std::string&>() == names[i]) return void(value = static_cast<E>(i));
        std::string what = j.is_string() ? j.get<std::string>() : j.dump();
        what.insert(0, 1, '\'').append("' is not a ").append(EnumNames<E>::noun);
        fail(place, what);
    }
    template <class T>
    static void read(const ResultJson& j, std::vector<T>& list, const JsonPlace& place) {
        if (!j.is_array()) fail(place, "not a list");
        list.assign(j.size(), T{});
        for (std::size_t i = 0; i < list.size(); ++i) read(j[i], list[i], JsonPlace{&place, {}, i});
    }
    template <Described T>
    static void read(const ResultJson& j, T& value, const JsonPlace& place) {
        FieldReader reader(object(j, place), place);
        fields(reader, value);
    }

private:
    /// The name of a named number and the number, for one element's description.
    struct EntryReader {
        const std::string& name;
        const ResultJson& number;
        const JsonPlace& place;
        void entry(std::string& n, double& value) {
            n = name;
            read(number, value, JsonPlace{&place, name});
        }
    };
    template <class T>
    static void read_entry(const std::string& name, const ResultJson& number, const JsonPlace& place,
                           std::vector<T>& list) {
        EntryReader reader{name, number, place};
        fields(reader, list.emplace_back());
    }
    [[noreturn]] static void fail(const JsonPlace& place, const std::string& what) {
        throw ResultFormatError(place.str() + ": " + what);
    }
    static const ResultJson& object(const ResultJson& j, const JsonPlace& place) {
        if (!j.is_object()) fail(place, "not an object");
        return j;
    }
    const ResultJson& member(const JsonPlace& place) const {
        const auto it = object(in_, place_).find(std::string(place.key));
        if (it == in_.end()) fail(place, "missing");
        return *it;
    }

    const ResultJson& in_;
    const JsonPlace& place_;
};

}  // namespace warpcheck

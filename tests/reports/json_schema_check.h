// A validator for the subset of JSON Schema that the results schema uses:
// $ref to "#/$defs/...", type, const, enum, anyOf, properties, required,
// additionalProperties, items, minimum, maximum. Keywords it does not know make
// it fail loudly, so the schema cannot drift outside what is checked.
#pragma once

#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace warpcheck::testing {

class SchemaValidator {
public:
    explicit SchemaValidator(nlohmann::json schema) : root_(std::move(schema)) {}

    /// The problems of `value` against the schema (empty: valid), each with its
    /// JSON pointer.
    std::vector<std::string> validate(const nlohmann::json& value) const {
        std::vector<std::string> problems;
        check(root_, value, "", problems);
        return problems;
    }

private:
    static bool has_type(const nlohmann::json& v, const std::string& type) {
        if (type == "object") return v.is_object();
        if (type == "array") return v.is_array();
        if (type == "string") return v.is_string();
        if (type == "boolean") return v.is_boolean();
        if (type == "null") return v.is_null();
        if (type == "integer") return v.is_number_integer();
        if (type == "number") return v.is_number();
        return false;
    }

    void check(const nlohmann::json& schema, const nlohmann::json& v, const std::string& at,
               std::vector<std::string>& problems) const {
        static const std::set<std::string> known = {
            "$schema", "$id", "$defs", "$ref", "title", "description", "type", "const", "enum", "anyOf",
            "properties", "required", "additionalProperties", "items", "minimum", "maximum"};
        for (const auto& [keyword, _] : schema.items())
            if (!known.count(keyword)) problems.push_back(at + ": schema keyword '" + keyword + "' is not supported by the test");
        const auto problem = [&](const std::string& what) { problems.push_back((at.empty() ? "/" : at) + ": " + what); };

        if (schema.contains("$ref")) {
            const std::string ref = schema["$ref"];
            const std::string prefix = "#/$defs/";
            if (ref.rfind(prefix, 0) != 0 || !root_["$defs"].contains(ref.substr(prefix.size())))
                return problem("unresolved $ref " + ref);
            check(root_["$defs"][ref.substr(prefix.size())], v, at, problems);
        }
        if (schema.contains("type")) {
            bool ok = false;
            if (schema["type"].is_array()) {
                for (const auto& t : schema["type"]) ok |= has_type(v, t);
            } else {
                ok = has_type(v, schema["type"]);
            }
            if (!ok) return problem("expected type " + schema["type"].dump() + ", got " + v.dump().substr(0, 60));
        }
        if (schema.contains("const") && v != schema["const"]) problem("expected " + schema["const"].dump());
        if (schema.contains("enum")) {
            bool found = false;
            for (const auto& e : schema["enum"]) found |= v == e;
            if (!found) problem(v.dump().substr(0, 60) + " is not one of " + schema["enum"].dump());
        }
        if (schema.contains("anyOf")) {
            bool any = false;
            for (const auto& option : schema["anyOf"]) {
                std::vector<std::string> sub;
                check(option, v, at, sub);
                any |= sub.empty();
            }
            if (!any) problem("matches none of anyOf: " + v.dump().substr(0, 60));
        }
        if (v.is_number()) {
            if (schema.contains("minimum") && v.get<double>() < schema["minimum"].get<double>()) problem("below the minimum");
            if (schema.contains("maximum") && v.get<double>() > schema["maximum"].get<double>()) problem("above the maximum");
        }
        if (v.is_object()) {
            if (schema.contains("required"))
                for (const auto& name : schema["required"])
                    if (!v.contains(name.get<std::string>())) problem("missing required " + name.dump());
            for (const auto& [name, member] : v.items()) {
                const std::string here = at + "/" + name;
                if (schema.contains("properties") && schema["properties"].contains(name)) {
                    check(schema["properties"][name], member, here, problems);
                } else if (schema.contains("additionalProperties")) {
                    const auto& extra = schema["additionalProperties"];
                    if (extra.is_boolean()) {
                        if (!extra.get<bool>()) problem("property '" + name + "' is not in the schema");
                    } else {
                        check(extra, member, here, problems);
                    }
                }
            }
        }
        if (v.is_array() && schema.contains("items"))
            for (std::size_t i = 0; i < v.size(); ++i) check(schema["items"], v[i], at + "/" + std::to_string(i), problems);
    }

    nlohmann::json root_;
};

}  // namespace warpcheck::testing

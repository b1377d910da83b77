// The members come from the model's descriptions (reports/result_json.h), with
// doubles as their bit patterns; the bytes are CBOR.
#include "validate/run/result_codec.h"

#include <cstdint>
#include <vector>

#include "reports/result_json.h"

namespace warpcheck {

std::string encode_result(const CheckResult& r) {
    // CBOR: compact, and strings from a warp's messages need not be valid UTF-8.
    const std::vector<uint8_t> bytes = ResultJson::to_cbor(FieldWriter<BitNumbers>::write(r));
    return std::string(bytes.begin(), bytes.end());
}

std::optional<CheckResult> decode_result(const std::string& bytes) {
    const ResultJson j = ResultJson::from_cbor(bytes, true, false);
    if (j.is_discarded()) return std::nullopt;
    try {
        CheckResult r;
        FieldReader<BitNumbers>::read(j, r, JsonPlace{nullptr, "result"});
        return r;
    } catch (const ResultFormatError&) {
        return std::nullopt;
    }
}

}  // namespace warpcheck

// A WPS server's answers (formats/wps/WpsDocuments.h): capabilities, process descriptions and
// execute responses, then the inputs of each described process checked and an Execute request
// written from them, as the Processes panel would; and the text as a CSV table output (the
// panel's plots).
#include "formats/wps/WpsDocuments.h"
#include "formats/wps/WpsForm.h"
#include "formats/wps/WpsJob.h"
#include "tests/fuzz/FuzzInput.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string_view text = orbis::fuzz::text(data, size);
    (void)orbis::wps::parseCapabilities(text, "fuzz");
    (void)orbis::wps::parseExecuteResponse(text, "fuzz");
    (void)orbis::wps::parseTable(text, "fuzz");
    if (auto processes = orbis::wps::parseProcessDescriptions(text, "fuzz")) {
        for (const auto& p : *processes) {
            std::vector<orbis::wps::InputValue> inputs;
            for (const auto& in : p.inputs) {
                orbis::wps::InputValue v{.identifier = in.identifier, .kind = in.kind};
                if (in.kind == orbis::wps::DataKind::Literal)
                    v.value = in.literal.defaultValue.value_or(in.literal.values.empty() ? "1" : in.literal.values.front());
                else if (in.kind == orbis::wps::DataKind::Complex)
                    v.value = "{}", v.format = in.defaultFormat;
                else
                    v.bbox = {0, 0, 1, 1}, v.crs = in.defaultCrs;
                inputs.push_back(std::move(v));
            }
            (void)orbis::wps::checkInputs(p, inputs);
            // The panel's form of it, filled from a drawn box, shape and point.
            auto form = orbis::wps::makeForm(p);
            (void)orbis::wps::bindPoint(form, {9.0, 46.0});
            for (auto& f : form)
                if (f.widget == orbis::wps::FieldWidget::File) f.send = false;   // no files read while fuzzing
            (void)orbis::wps::formInputs(p, form, {.bounds = std::array<double, 4>{0, 0, 1, 1}, .geoJson = "{}", .point = std::array<double, 2>{9, 46}});
            (void)orbis::wps::executeRequest(p.identifier, inputs, {}, p.storeSupported);
        }
    }
    return 0;
}

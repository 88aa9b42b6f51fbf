// A live PostgreSQL layer's outside input: NOTIFY payloads (the changed box, from whatever
// trigger sends on the channel) and connection strings (from scene files) as libpq reads them.
#include "layers/vector/PgListener.h"
#include "tests/fuzz/FuzzInput.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string text(orbis::fuzz::text(data, size));
    if (auto box = orbis::vector::parseChangeBox(text)) {
        if (!(box->south <= box->north && box->west <= box->east)) __builtin_trap();
    }
    (void)orbis::vector::libpqConnection("PG:" + text);
    return 0;
}

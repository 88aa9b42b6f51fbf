#include "globe/WmsTime.h"

#include <gtest/gtest.h>

namespace orbis::globe {
namespace {

std::vector<std::string> texts(const std::vector<WmsTimeValue>& v) {
    std::vector<std::string> out;
    for (const auto& x : v) out.push_back(x.text);
    return out;
}

TEST(WmsTime, ListsAndIntervalsExpandInOrder) {
    auto months = parseWmsTimeExtent("2026-01-31/2026-05-01/P1M");
    ASSERT_TRUE(months) << months.message();
    // The day is kept, or the month's last day when it is shorter; never drifting (Mar 31, not 28).
    EXPECT_EQ(texts(*months), (std::vector<std::string>{"2026-01-31", "2026-02-28", "2026-03-31", "2026-04-30"}));
    auto hours = parseWmsTimeExtent("2026-06-01T00:00:00Z/2026-06-01T12:00:00Z/PT6H, 2026-05-01");
    ASSERT_TRUE(hours) << hours.message();
    EXPECT_EQ(texts(*hours), (std::vector<std::string>{"2026-05-01", "2026-06-01T00:00:00Z", "2026-06-01T06:00:00Z",
                                                       "2026-06-01T12:00:00Z"}));
    auto leap = parseWmsTimeExtent("2024-02-29/2028-03-01/P1Y");
    ASSERT_TRUE(leap) << leap.message();
    EXPECT_EQ(texts(*leap), (std::vector<std::string>{"2024-02-29", "2025-02-28", "2026-02-28", "2027-02-28", "2028-02-29"}));
    auto list = parseWmsTimeExtent(" 2026-03-01 ,2026-01-01,2026-03-01");
    ASSERT_TRUE(list) << list.message();
    EXPECT_EQ(texts(*list), (std::vector<std::string>{"2026-01-01", "2026-03-01"})) << "sorted, repeats dropped";
    auto weeks = parseWmsTimeExtent("1969-12-25/1970-01-08/P1W");   // before the epoch
    ASSERT_TRUE(weeks) << weeks.message();
    EXPECT_EQ(texts(*weeks), (std::vector<std::string>{"1969-12-25", "1970-01-01", "1970-01-08"}));
}

TEST(WmsTime, TheValueInEffectIsTheLastStartedOne) {
    auto v = parseWmsTimeExtent("2026-01-01/2026-03-01/P1M");
    ASSERT_TRUE(v);
    const auto at = [&](const char* iso) { return wmsTimeIndexAt(*v, *parseIso8601(iso)); };
    EXPECT_EQ(at("2025-06-01"), 0u) << "before the first: the first";
    EXPECT_EQ(at("2026-01-01"), 0u);
    EXPECT_EQ(at("2026-01-31T23:59:59Z"), 0u);
    EXPECT_EQ(at("2026-02-01"), 1u);
    EXPECT_EQ(at("2030-01-01"), 2u) << "after the last: the last";
}

TEST(WmsTime, BadExtentsAreClearErrors) {
    const struct { const char* extent; const char* says; } cases[] = {
        {"", "empty"},
        {"2026-01-01,,2026-02-01", "empty value"},
        {"2026-13-01", "2026-13-01"},
        {"2026-01-01/2026-02-01", "no period"},
        {"2026-02-01/2026-01-01/P1D", "ends before it starts"},
        {"2026-01-01/2026-02-01/P0D", "P0D"},
        {"2026-01-01/2026-02-01/1D", "not an ISO 8601 period"},
        {"2026-01-01/2026-02-01/PT1.5S", "PT1.5S"},
        {"2000-01-01/2030-01-01/PT1S", "more than 100000 values"},
    };
    for (const auto& c : cases) {
        auto r = parseWmsTimeExtent(c.extent);
        ASSERT_FALSE(r) << c.extent;
        EXPECT_NE(r.message().find(c.says), std::string::npos) << c.extent << " -> " << r.message();
    }
}

TEST(WmsTime, HugePeriodsEndTheIntervalInsteadOfOverflowing) {
    // Found by fuzz-wms-time: a period of 777777770 days overflowed the nanosecond arithmetic.
    for (const char* extent : {"2020-01-01/2261-12-31/P777777770D", "2020-01-01/2261-12-31/P999999999Y999999999Y",
                               "2020-01-01/2261-12-31/PT999999999H", "1700-01-01/2261-12-31/P100Y"}) {
        auto r = parseWmsTimeExtent(extent);
        ASSERT_TRUE(r) << extent << ": " << r.message();
        ASSERT_FALSE(r->empty()) << extent;
        EXPECT_EQ(r->front().text.substr(0, 4), std::string(extent).substr(0, 4)) << extent;
    }
    auto century = parseWmsTimeExtent("1700-01-01/2261-12-31/P100Y");
    ASSERT_TRUE(century);
    EXPECT_EQ(century->size(), 6u) << "1700 .. 2200";
}

}  // namespace
}  // namespace orbis::globe

// NMEA 0183 sentences (Nmea.h): checksums, fields of GGA / RMC / VTG, and what is refused.
// The "classic" sentences are the well-known examples from the NMEA literature and the u-blox
// protocol specification, with their published checksums: they check our checksum independently
// of our own writer.

#include "formats/livefeed/Nmea.h"
#include "formats/livefeed/NmeaWriter.h"

#include <gtest/gtest.h>

namespace orbis::livefeed {
namespace {

constexpr const char* kClassicGga = "$GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,*47";
constexpr const char* kClassicRmc = "$GPRMC,123519,A,4807.038,N,01131.000,E,022.4,084.4,230394,003.1,W*6A";

// Angles: 1e-9 degree is far below the 1e-3 arc minute (2 m) of the input; exact arithmetic
// would do, but the minutes go through a double division.
constexpr double kAngleTol = 1e-9;
constexpr double kValueTol = 1e-9;

TEST(Nmea, ChecksumOfClassicSentencesIsThePublishedOne) {
    EXPECT_EQ(nmeaChecksum("GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,"), 0x47);
    EXPECT_EQ(nmeaChecksum("GPRMC,123519,A,4807.038,N,01131.000,E,022.4,084.4,230394,003.1,W"), 0x6A);
    EXPECT_EQ(nmeaSentence("GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,"), std::string(kClassicGga) + "\r\n");
}

TEST(Nmea, ClassicGgaDecodesEveryField) {
    const NmeaSentence s = parseNmeaSentence(kClassicGga);
    ASSERT_EQ(s.status, NmeaStatus::Ok) << s.error;
    EXPECT_EQ(s.talker, "GP");
    EXPECT_EQ(s.type, "GGA");
    const auto& g = std::get<NmeaGga>(s.data);
    EXPECT_EQ(*g.timeOfDay, (12 * 3600 + 35 * 60 + 19) * kNsPerSecond);
    EXPECT_NEAR(*g.latDeg, 48.0 + 7.038 / 60.0, kAngleTol);
    EXPECT_NEAR(*g.lonDeg, 11.0 + 31.0 / 60.0, kAngleTol);
    EXPECT_EQ(g.quality, 1);
    EXPECT_EQ(g.satellites, 8);
    EXPECT_NEAR(*g.hdop, 0.9, kValueTol);
    EXPECT_NEAR(*g.altitudeMsl, 545.4, kValueTol);
    EXPECT_NEAR(*g.geoidSeparation, 46.9, kValueTol);
    EXPECT_TRUE(g.hasPosition());
}

TEST(Nmea, ClassicRmcDecodesEveryField) {
    const NmeaSentence s = parseNmeaSentence(kClassicRmc);
    ASSERT_EQ(s.status, NmeaStatus::Ok) << s.error;
    const auto& r = std::get<NmeaRmc>(s.data);
    EXPECT_EQ(*r.timeOfDay, (12 * 3600 + 35 * 60 + 19) * kNsPerSecond);
    EXPECT_TRUE(r.active);
    EXPECT_NEAR(*r.latDeg, 48.1173, kAngleTol);
    EXPECT_NEAR(*r.speedMps, 22.4 * 1852.0 / 3600.0, kValueTol);   // 11.5236 m/s
    EXPECT_NEAR(*r.courseDeg, 84.4, kValueTol);
    ASSERT_TRUE(r.date);
    EXPECT_EQ(r.date->year, 1994);
    EXPECT_EQ(r.date->month, 3);
    EXPECT_EQ(r.date->day, 23);
    EXPECT_NEAR(*r.magneticVariationDeg, -3.1, kValueTol);   // 003.1,W
    EXPECT_EQ(r.mode, 0);                                     // NMEA 2.1: no mode field
}

TEST(Nmea, UbloxSentencesWithModeAndFractionalSecondsDecode) {
    const NmeaSentence gga = parseNmeaSentence("$GPGGA,092725.00,4717.11399,N,00833.91590,E,1,08,1.01,499.6,M,48.0,M,,*5B");
    ASSERT_EQ(gga.status, NmeaStatus::Ok) << gga.error;
    EXPECT_NEAR(*std::get<NmeaGga>(gga.data).lonDeg, 8.0 + 33.91590 / 60.0, kAngleTol);
    const NmeaSentence rmc = parseNmeaSentence("$GPRMC,083559.00,A,4717.11437,N,00833.91522,E,0.004,77.52,091202,,,A*57");
    ASSERT_EQ(rmc.status, NmeaStatus::Ok) << rmc.error;
    EXPECT_EQ(std::get<NmeaRmc>(rmc.data).mode, 'A');
    EXPECT_EQ(std::get<NmeaRmc>(rmc.data).date->year, 2002);
    EXPECT_FALSE(std::get<NmeaRmc>(rmc.data).magneticVariationDeg);
    const NmeaSentence vtg = parseNmeaSentence("$GPVTG,77.52,T,,M,0.004,N,0.008,K,A*06");
    ASSERT_EQ(vtg.status, NmeaStatus::Ok) << vtg.error;
    const auto& v = std::get<NmeaVtg>(vtg.data);
    EXPECT_NEAR(*v.courseTrueDeg, 77.52, kValueTol);
    EXPECT_FALSE(v.courseMagneticDeg);
    EXPECT_NEAR(*v.speedMps(), 0.008 / 3.6, kValueTol);   // km/h preferred over knots
}

TEST(Nmea, SouthAndWestAreNegativeForAnyTalker) {
    for (const char* talker : {"GP", "GN", "GL", "GA", "GB", "BD"}) {
        const std::string line = nmeaSentence(std::string(talker) + "GGA,000001.50,3351.5000,S,15112.7500,W,2,12,0.6,12.0,M,-20.5,M,1.2,0000");
        const NmeaSentence s = parseNmeaSentence(line);
        ASSERT_EQ(s.status, NmeaStatus::Ok) << s.error;
        EXPECT_EQ(s.talker, talker);
        const auto& g = std::get<NmeaGga>(s.data);
        EXPECT_NEAR(*g.latDeg, -(33.0 + 51.5 / 60.0), kAngleTol);
        EXPECT_NEAR(*g.lonDeg, -(151.0 + 12.75 / 60.0), kAngleTol);
        EXPECT_EQ(*g.timeOfDay, kNsPerSecond + kNsPerSecond / 2);
        EXPECT_NEAR(*g.geoidSeparation, -20.5, kValueTol);
        EXPECT_EQ(g.quality, 2);
    }
}

TEST(Nmea, WrongChecksumIsRefused) {
    std::string line = kClassicGga;
    line[20] = '9';   // a digit of the latitude changed; the checksum no longer matches
    const NmeaSentence s = parseNmeaSentence(line);
    EXPECT_EQ(s.status, NmeaStatus::BadChecksum);
    EXPECT_NE(s.error.find("checksum 47"), std::string::npos) << s.error;
    EXPECT_TRUE(std::holds_alternative<std::monostate>(s.data));
    const std::string classic = kClassicGga;
    EXPECT_EQ(parseNmeaSentence(classic.substr(0, classic.find('*')) + "*4G").status, NmeaStatus::Malformed);
}

TEST(Nmea, MissingChecksumIsRefusedUnlessMadeOptional) {
    const std::string bare = std::string(kClassicGga).substr(0, std::string(kClassicGga).find('*'));
    EXPECT_EQ(parseNmeaSentence(bare).status, NmeaStatus::BadChecksum);
    EXPECT_NE(parseNmeaSentence(bare).error.find("no checksum"), std::string::npos);
    NmeaOptions lenient;
    lenient.requireChecksum = false;
    EXPECT_EQ(parseNmeaSentence(bare, lenient).status, NmeaStatus::Ok);
    std::string wrong = kClassicGga;
    wrong.back() = '8';
    EXPECT_EQ(parseNmeaSentence(wrong, lenient).status, NmeaStatus::BadChecksum);   // present and wrong: always refused
}

TEST(Nmea, EmptyFieldsOfAReceiverWithoutFixAreNoValueNotErrors) {
    const NmeaSentence gga = parseNmeaSentence("$GPGGA,,,,,,0,00,99.99,,,,,,*48");
    ASSERT_EQ(gga.status, NmeaStatus::Ok) << gga.error;
    EXPECT_FALSE(std::get<NmeaGga>(gga.data).hasPosition());
    EXPECT_FALSE(std::get<NmeaGga>(gga.data).altitudeMsl);
    const NmeaSentence rmc = parseNmeaSentence("$GPRMC,,V,,,,,,,,,,N*53");
    ASSERT_EQ(rmc.status, NmeaStatus::Ok) << rmc.error;
    EXPECT_FALSE(std::get<NmeaRmc>(rmc.data).hasPosition());
    const NmeaSentence vtg = parseNmeaSentence("$GPVTG,,,,,,,,,N*30");
    ASSERT_EQ(vtg.status, NmeaStatus::Ok) << vtg.error;
    EXPECT_FALSE(std::get<NmeaVtg>(vtg.data).speedMps());
}

TEST(Nmea, QualityZeroAndVoidStatusHaveNoPosition) {
    const NmeaSentence gga = parseNmeaSentence(nmeaSentence("GPGGA,123519,4807.038,N,01131.000,E,0,08,0.9,545.4,M,46.9,M,,"));
    ASSERT_EQ(gga.status, NmeaStatus::Ok);
    EXPECT_TRUE(std::get<NmeaGga>(gga.data).latDeg);
    EXPECT_FALSE(std::get<NmeaGga>(gga.data).hasPosition());
    const NmeaSentence rmc = parseNmeaSentence(nmeaSentence("GPRMC,123519,V,4807.038,N,01131.000,E,022.4,084.4,230394,003.1,W"));
    ASSERT_EQ(rmc.status, NmeaStatus::Ok);
    EXPECT_FALSE(std::get<NmeaRmc>(rmc.data).hasPosition());
    const NmeaSentence modeN = parseNmeaSentence(nmeaSentence("GPRMC,123519,A,4807.038,N,01131.000,E,022.4,084.4,230394,,,N"));
    ASSERT_EQ(modeN.status, NmeaStatus::Ok);
    EXPECT_FALSE(std::get<NmeaRmc>(modeN.data).hasPosition());
}

TEST(Nmea, BrokenFieldsAreMalformedWithAReason) {
    struct Case {
        const char* body;
        const char* reason;
    };
    const Case cases[] = {
        {"GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M", "GGA has 10 fields"},
        {"GPGGA,123519,4867.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,", "bad latitude"},     // 67 minutes
        {"GPGGA,123519,9107.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,", "bad latitude"},     // 91 degrees
        {"GPGGA,123519,4807.038,X,01131.000,E,1,08,0.9,545.4,M,46.9,M,,", "bad latitude"},     // hemisphere
        {"GPGGA,123519,4807.038,N,01131.000,N,1,08,0.9,545.4,M,46.9,M,,", "bad longitude"},
        {"GPGGA,123519,4807.038,N,,,1,08,0.9,545.4,M,46.9,M,,", "latitude without longitude"},
        {"GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,54x.4,M,46.9,M,,", "bad number"},
        {"GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,F,46.9,M,,", "altitude unit"},
        {"GPGGA,246000,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,", "bad UTC time"},
        {"GPGGA,,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,", "position without UTC time"},
        {"GPRMC,123519,A,4807.038,N,01131.000,E,022.4,084.4,300294,003.1,W", "bad date"},    // 30 February
        {"GPRMC,123519,X,4807.038,N,01131.000,E,022.4,084.4,230394,003.1,W", "neither A nor V"},
        {"GPRMC,123519,A,4807.038,N,01131.000,E,022.4,084.4,,003.1,W", "without UTC time or date"},
        {"GPVTG,77.52,T,,M,0.004,N,0.008", "VTG has 7 fields"},
        {"GPVTG,77.52,X,,M,0.004,N,0.008,K,A", "unit letters"},
        {"GPG,1,2", "not talker + type"},
    };
    for (const Case& c : cases) {
        const NmeaSentence s = parseNmeaSentence(nmeaSentence(c.body));
        EXPECT_EQ(s.status, NmeaStatus::Malformed) << c.body;
        EXPECT_NE(s.error.find(c.reason), std::string::npos) << c.body << " -> " << s.error;
        EXPECT_NE(s.error.find(std::string(c.body).substr(0, 12)), std::string::npos) << "quotes the sentence: " << s.error;
    }
}

TEST(Nmea, OtherSentenceTypesAreUnknownNotErrors) {
    const NmeaSentence gsv = parseNmeaSentence(nmeaSentence("GPGSV,3,1,11,03,03,111,00,04,15,270,00,06,01,010,00,13,06,292,00"));
    EXPECT_EQ(gsv.status, NmeaStatus::UnknownType);
    EXPECT_EQ(gsv.type, "GSV");
    const NmeaSentence ubx = parseNmeaSentence(nmeaSentence("PUBX,00,081350.00,4717.113210,N,00833.915187,E"));
    EXPECT_EQ(ubx.status, NmeaStatus::UnknownType);
    EXPECT_EQ(ubx.talker, "P");
}

TEST(Nmea, TimeOfDayKeepsNanoseconds) {
    EXPECT_EQ(parseNmeaTimeOfDay("000000"), 0);
    EXPECT_EQ(parseNmeaTimeOfDay("235959.999999999"), kNsPerDay - 1);
    EXPECT_EQ(parseNmeaTimeOfDay("120000.5"), 12 * 3600 * kNsPerSecond + kNsPerSecond / 2);
    EXPECT_EQ(parseNmeaTimeOfDay("235960"), kNsPerDay);   // leap second: the next day's first instant
    EXPECT_FALSE(parseNmeaTimeOfDay("12000"));
    EXPECT_FALSE(parseNmeaTimeOfDay("125960.0"));
    EXPECT_FALSE(parseNmeaTimeOfDay("120000,5"));
}

TEST(Nmea, SentenceMustStartWithDollar) {
    EXPECT_EQ(parseNmeaSentence(std::string(kClassicGga).substr(1)).status, NmeaStatus::Malformed);
    EXPECT_EQ(parseNmeaSentence("").status, NmeaStatus::Malformed);
    EXPECT_EQ(parseNmeaSentence(std::string(kClassicGga) + "\r\n").status, NmeaStatus::Ok);
}

}  // namespace
}  // namespace orbis::livefeed

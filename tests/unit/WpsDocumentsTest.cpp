// WPS 1.0.0 documents (formats/wps/WpsDocuments.h) in the shape PyWPS 4.5's templates give them
// (pywps/templates/1.0.0): capabilities, a description with literal inputs (ranges, allowed
// values, defaults), complex and bounding-box inputs and outputs, execute responses in every
// state with outputs inline and by reference; the Execute request written back and read by
// GDAL's XML parser; inputs checked against the description; exception reports and bad
// documents refused with their reason.
#include "formats/wps/WpsClient.h"
#include "formats/wps/WpsDocuments.h"
#include "formats/wps/WpsForm.h"
#include "formats/wps/WpsJob.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <unistd.h>

#include <cpl_minixml.h>
#include <gtest/gtest.h>

#include <memory>

namespace orbis::wps {
namespace {

const char* kCapabilities = R"(<?xml version="1.0" encoding="UTF-8"?>
<!-- PyWPS 4.5.2 -->
<wps:Capabilities service="WPS" version="1.0.0" xml:lang="en-US" xmlns:xlink="http://www.w3.org/1999/xlink" xmlns:wps="http://www.opengis.net/wps/1.0.0" xmlns:ows="http://www.opengis.net/ows/1.1" updateSequence="1">
    <ows:ServiceIdentification>
        <ows:Title>Orbis demo processes</ows:Title>
        <ows:Abstract>Terrain analysis</ows:Abstract>
        <ows:ServiceType>WPS</ows:ServiceType>
        <ows:ServiceTypeVersion>1.0.0</ows:ServiceTypeVersion>
    </ows:ServiceIdentification>
    <ows:ServiceProvider><ows:ProviderName>Orbis</ows:ProviderName></ows:ServiceProvider>
    <ows:OperationsMetadata>
        <ows:Operation name="GetCapabilities"><ows:DCP><ows:HTTP><ows:Get xlink:href="http://127.0.0.1:5000/wps"/></ows:HTTP></ows:DCP></ows:Operation>
        <ows:Operation name="DescribeProcess"><ows:DCP><ows:HTTP><ows:Get xlink:href="http://127.0.0.1:5000/wps"/><ows:Post xlink:href="http://127.0.0.1:5000/wps"/></ows:HTTP></ows:DCP></ows:Operation>
        <ows:Operation name="Execute"><ows:DCP><ows:HTTP><ows:Get xlink:href="http://127.0.0.1:5000/wps"/><ows:Post xlink:href="http://127.0.0.1:5000/wps"/></ows:HTTP></ows:DCP></ows:Operation>
    </ows:OperationsMetadata>
    <wps:ProcessOfferings>
        <wps:Process wps:processVersion="1.0">
            <ows:Identifier>slope</ows:Identifier>
            <ows:Title>Slope of the DEM in an area</ows:Title>
            <ows:Abstract>gdaldem slope</ows:Abstract>
        </wps:Process>
        <wps:Process wps:processVersion="2.1">
            <ows:Identifier>sleep</ows:Identifier>
            <ows:Title>A long task</ows:Title>
        </wps:Process>
    </wps:ProcessOfferings>
    <wps:Languages><wps:Default><ows:Language>en-US</ows:Language></wps:Default></wps:Languages>
</wps:Capabilities>)";

const char* kDescription = R"(<?xml version="1.0" encoding="UTF-8"?>
<wps:ProcessDescriptions xmlns:wps="http://www.opengis.net/wps/1.0.0" xmlns:ows="http://www.opengis.net/ows/1.1" xmlns:xlink="http://www.w3.org/1999/xlink" service="WPS" version="1.0.0" xml:lang="en-US">
    <ProcessDescription wps:processVersion="1.0" storeSupported="true" statusSupported="true">
        <ows:Identifier>slope</ows:Identifier>
        <ows:Title>Slope of the DEM in an area</ows:Title>
        <ows:Abstract>gdaldem slope</ows:Abstract>
        <DataInputs>
            <Input minOccurs="1" maxOccurs="1">
                <ows:Identifier>area</ows:Identifier>
                <ows:Title>Area</ows:Title>
                <ows:Abstract></ows:Abstract>
                <BoundingBoxData>
                    <Default><CRS>epsg:4326</CRS></Default>
                    <Supported><CRS>epsg:4326</CRS><CRS>epsg:3857</CRS></Supported>
                </BoundingBoxData>
            </Input>
            <Input minOccurs="0" maxOccurs="1">
                <ows:Identifier>scale</ows:Identifier>
                <ows:Title>Vertical scale</ows:Title>
                <ows:Abstract></ows:Abstract>
                <LiteralData>
                    <ows:DataType ows:reference="http://www.w3.org/TR/xmlschema-2/#float">float</ows:DataType>
                    <ows:AllowedValues>
                        <ows:Range ows:rangeClosure="closed">
                            <ows:MinimumValue>0.1</ows:MinimumValue>
                            <ows:MaximumValue>10</ows:MaximumValue>
                        </ows:Range>
                    </ows:AllowedValues>
                    <DefaultValue>1.0</DefaultValue>
                </LiteralData>
            </Input>
            <Input minOccurs="1" maxOccurs="1">
                <ows:Identifier>unit</ows:Identifier>
                <ows:Title>Unit</ows:Title>
                <LiteralData>
                    <ows:DataType ows:reference="http://www.w3.org/TR/xmlschema-2/#string">string</ows:DataType>
                    <ows:AllowedValues><ows:Value>degrees</ows:Value><ows:Value>percent</ows:Value></ows:AllowedValues>
                </LiteralData>
            </Input>
            <Input minOccurs="0" maxOccurs="3">
                <ows:Identifier>steps</ows:Identifier>
                <ows:Title>Smoothing passes</ows:Title>
                <LiteralData>
                    <ows:DataType ows:reference="http://www.w3.org/TR/xmlschema-2/#integer">integer</ows:DataType>
                    <ows:AnyValue/>
                </LiteralData>
            </Input>
            <Input minOccurs="0" maxOccurs="1">
                <ows:Identifier>mask</ows:Identifier>
                <ows:Title>Mask polygons</ows:Title>
                <ComplexData maximumMegabytes="3">
                    <Default><Format><MimeType>application/geo+json</MimeType></Format></Default>
                    <Supported>
                        <Format><MimeType>application/geo+json</MimeType></Format>
                        <Format><MimeType>application/gml+xml</MimeType></Format>
                    </Supported>
                </ComplexData>
            </Input>
        </DataInputs>
        <ProcessOutputs>
            <Output>
                <ows:Identifier>slope</ows:Identifier>
                <ows:Title>Slope raster</ows:Title>
                <ComplexOutput>
                    <Default><Format><MimeType>image/tiff; subtype=geotiff</MimeType></Format></Default>
                    <Supported><Format><MimeType>image/tiff; subtype=geotiff</MimeType></Format></Supported>
                </ComplexOutput>
            </Output>
            <Output>
                <ows:Identifier>mean</ows:Identifier>
                <ows:Title>Mean slope</ows:Title>
                <LiteralOutput><ows:DataType ows:reference="http://www.w3.org/TR/xmlschema-2/#float">float</ows:DataType><ows:AnyValue/></LiteralOutput>
            </Output>
        </ProcessOutputs>
    </ProcessDescription>
</wps:ProcessDescriptions>)";

std::string response(const std::string& status, const std::string& outputs = "") {
    return R"(<?xml version="1.0" encoding="UTF-8"?>
<wps:ExecuteResponse xmlns:wps="http://www.opengis.net/wps/1.0.0" xmlns:ows="http://www.opengis.net/ows/1.1" xmlns:xlink="http://www.w3.org/1999/xlink" service="WPS" version="1.0.0" xml:lang="en-US" serviceInstance="http://127.0.0.1:5000/wps?service=WPS&amp;request=GetCapabilities" statusLocation="http://127.0.0.1:5000/outputs/7c1e.xml">
    <wps:Process wps:processVersion="1.0"><ows:Identifier>slope</ows:Identifier><ows:Title>Slope</ows:Title></wps:Process>
    <wps:Status creationTime="2026-12-04T17:00:00Z">)" +
           status + "</wps:Status>" + outputs + "</wps:ExecuteResponse>";
}

TEST(WpsDocuments, CapabilitiesListTheProcessesAndWhereToAsk) {
    auto c = parseCapabilities(kCapabilities, "demo");
    ASSERT_TRUE(c) << c.message();
    EXPECT_EQ(c->title, "Orbis demo processes");
    EXPECT_EQ(c->version, "1.0.0");
    EXPECT_EQ(c->provider, "Orbis");
    ASSERT_EQ(c->processes.size(), 2u);
    EXPECT_EQ(c->processes[0].identifier, "slope");
    EXPECT_EQ(c->processes[0].abstract, "gdaldem slope");
    EXPECT_EQ(c->processes[1].version, "2.1");
    EXPECT_EQ(c->executePost, "http://127.0.0.1:5000/wps");
    EXPECT_EQ(c->describeGet, "http://127.0.0.1:5000/wps");
}

TEST(WpsDocuments, ADescriptionGivesEveryInputsTypeRangeChoicesAndFormats) {
    auto all = parseProcessDescriptions(kDescription, "demo");
    ASSERT_TRUE(all) << all.message();
    ASSERT_EQ(all->size(), 1u);
    const ProcessDescription& d = all->front();
    EXPECT_TRUE(d.storeSupported && d.statusSupported);
    ASSERT_EQ(d.inputs.size(), 5u);
    const Parameter* area = d.input("area");
    ASSERT_TRUE(area);
    EXPECT_EQ(area->kind, DataKind::BoundingBox);
    EXPECT_EQ(area->defaultCrs, "epsg:4326");
    EXPECT_EQ(area->crss.size(), 2u);
    const Parameter* scale = d.input("scale");
    ASSERT_TRUE(scale);
    EXPECT_EQ(scale->minOccurs, 0);
    EXPECT_EQ(scale->literal.dataType, "float");
    EXPECT_FALSE(scale->literal.anyValue);
    ASSERT_EQ(scale->literal.ranges.size(), 1u);
    EXPECT_DOUBLE_EQ(scale->literal.ranges[0].min, 0.1);
    EXPECT_DOUBLE_EQ(scale->literal.ranges[0].max, 10.0);
    EXPECT_EQ(scale->literal.defaultValue.value_or(""), "1.0");
    EXPECT_EQ(d.input("unit")->literal.values, (std::vector<std::string>{"degrees", "percent"}));
    EXPECT_TRUE(d.input("steps")->literal.anyValue);
    EXPECT_EQ(d.input("steps")->maxOccurs, 3);
    const Parameter* mask = d.input("mask");
    EXPECT_EQ(mask->kind, DataKind::Complex);
    EXPECT_EQ(mask->formats.size(), 2u);
    EXPECT_DOUBLE_EQ(mask->maximumMegabytes, 3.0);
    ASSERT_EQ(d.outputs.size(), 2u);
    EXPECT_EQ(d.output("slope")->defaultFormat.mimeType, "image/tiff; subtype=geotiff");
    EXPECT_EQ(d.output("mean")->literal.dataType, "float");
}

TEST(WpsDocuments, InputsAreCheckedAgainstTheDescription) {
    auto all = parseProcessDescriptions(kDescription, "demo");
    ASSERT_TRUE(all);
    const ProcessDescription& d = all->front();
    InputValue area{.identifier = "area", .kind = DataKind::BoundingBox, .bbox = {6.0, 45.0, 7.0, 46.0}, .crs = "epsg:4326"};
    InputValue unit{.identifier = "unit", .value = "percent"};
    const std::vector<InputValue> good = {area, unit, {.identifier = "scale", .value = "2.5"}, {.identifier = "steps", .value = "2"}};
    EXPECT_TRUE(checkInputs(d, good));
    const struct { std::vector<InputValue> inputs; const char* says; } bad[] = {
        {{unit}, "input \"area\" is required"},
        {{area, {.identifier = "unit", .value = "radians"}}, "\"radians\" is not allowed (degrees, percent)"},
        {{area, unit, {.identifier = "scale", .value = "20"}}, "\"20\" is not allowed (0.10000000000000001 .. 10)"},
        {{area, unit, {.identifier = "scale", .value = "steep"}}, "\"steep\" is not a number"},
        {{area, unit, {.identifier = "steps", .value = "1.5"}}, "1.5 is not a whole number"},
        {{area, unit, {.identifier = "colour", .value = "red"}}, "slope has no input \"colour\""},
        {{area, unit, {.identifier = "steps", .value = "1"}, {.identifier = "steps", .value = "1"}, {.identifier = "steps", .value = "1"},
          {.identifier = "steps", .value = "1"}},
         "given 4 times, at most 3"},
        {{{.identifier = "area", .kind = DataKind::BoundingBox, .bbox = {7.0, 45.0, 6.0, 46.0}}, unit}, "lower corner"},
        {{area, unit, {.identifier = "mask", .kind = DataKind::Complex, .value = "{}", .format = {.mimeType = "text/csv"}}}, "takes no text/csv"},
        {{area, unit, {.identifier = "mask", .value = "{}"}}, "input \"mask\" is complex data"},
    };
    for (const auto& b : bad) {
        auto r = checkInputs(d, b.inputs);
        ASSERT_FALSE(r) << b.says;
        EXPECT_NE(r.message().find(b.says), std::string::npos) << r.message();
    }
}

TEST(WpsDocuments, AnExecuteRequestIsValidXmlWithEveryKindOfInput) {
    const std::vector<InputValue> inputs = {
        {.identifier = "area", .kind = DataKind::BoundingBox, .bbox = {6.0, 45.0, 7.5, 46.25}, .crs = "epsg:4326"},
        {.identifier = "unit", .value = "a<b & \"c\""},
        {.identifier = "mask", .kind = DataKind::Complex, .value = R"({"type": "FeatureCollection", "note": "]]>"})",
         .format = {.mimeType = "application/geo+json"}},
        {.identifier = "gml", .kind = DataKind::Complex, .value = "<?xml version=\"1.0\"?><gml:Point><gml:pos>1 2</gml:pos></gml:Point>",
         .format = {.mimeType = "application/gml+xml"}},
        {.identifier = "dem", .kind = DataKind::Complex, .format = {.mimeType = "image/tiff"}, .reference = "http://127.0.0.1:8080/dem.tif?a=1&b=2"},
    };
    const std::vector<OutputRequest> outputs = {{.identifier = "slope", .asReference = true}};
    const std::string x = executeRequest("slope", inputs, outputs, true);
    std::unique_ptr<CPLXMLNode, decltype(&CPLDestroyXMLNode)> doc(CPLParseXMLString(x.c_str()), &CPLDestroyXMLNode);
    ASSERT_TRUE(doc) << x;
    CPLStripXMLNamespace(doc.get(), nullptr, TRUE);
    const CPLXMLNode* root = CPLGetXMLNode(doc.get(), "=Execute");
    ASSERT_TRUE(root) << x;
    EXPECT_STREQ(CPLGetXMLValue(root, "Identifier", ""), "slope");
    EXPECT_STREQ(CPLGetXMLValue(root, "ResponseForm.ResponseDocument.storeExecuteResponse", ""), "true");
    EXPECT_STREQ(CPLGetXMLValue(root, "ResponseForm.ResponseDocument.Output.asReference", ""), "true");
    const CPLXMLNode* in = CPLGetXMLNode(root, "DataInputs.Input");
    ASSERT_TRUE(in);
    EXPECT_STREQ(CPLGetXMLValue(in, "Data.BoundingBoxData.LowerCorner", ""), "45 6") << "EPSG:4326's axis order: latitude first";
    in = in->psNext;
    while (in && in->eType != CXT_Element) in = in->psNext;
    ASSERT_TRUE(in);
    EXPECT_STREQ(CPLGetXMLValue(in, "Data.LiteralData", ""), "a<b & \"c\"") << "escaped and read back";
    EXPECT_NE(x.find("]]]]><![CDATA[>"), std::string::npos) << "a CDATA end inside the data is split";
    EXPECT_NE(x.find("<gml:Point>"), std::string::npos) << "XML data goes in as elements";
    EXPECT_EQ(x.find("<?xml version=\"1.0\"?><gml:Point>"), std::string::npos) << "without its declaration";
    EXPECT_NE(x.find("xlink:href=\"http://127.0.0.1:8080/dem.tif?a=1&amp;b=2\""), std::string::npos);
    const std::string sync = executeRequest("slope", {}, {}, false);
    EXPECT_EQ(sync.find("storeExecuteResponse"), std::string::npos);
}

TEST(WpsDocuments, ExecuteResponsesInEveryState) {
    auto accepted = parseExecuteResponse(response(R"(<wps:ProcessAccepted percentCompleted="0">PyWPS Process slope accepted</wps:ProcessAccepted>)"), "demo");
    ASSERT_TRUE(accepted) << accepted.message();
    EXPECT_EQ(accepted->state, JobState::Accepted);
    EXPECT_EQ(accepted->statusLocation, "http://127.0.0.1:5000/outputs/7c1e.xml");
    EXPECT_FALSE(accepted->finished());
    auto started = parseExecuteResponse(response(R"(<wps:ProcessStarted percentCompleted="40">tile 4 of 10</wps:ProcessStarted>)"), "demo");
    ASSERT_TRUE(started);
    EXPECT_EQ(started->state, JobState::Started);
    EXPECT_EQ(started->percent, 40);
    EXPECT_EQ(started->message, "tile 4 of 10");
    auto failed = parseExecuteResponse(response(R"(<wps:ProcessFailed><wps:ExceptionReport><ows:Exception exceptionCode="NoApplicableCode" locator="None"><ows:ExceptionText>Process error: the area is outside the DEM</ows:ExceptionText></ows:Exception></wps:ExceptionReport></wps:ProcessFailed>)"), "demo");
    ASSERT_TRUE(failed);
    EXPECT_EQ(failed->state, JobState::Failed);
    EXPECT_EQ(failed->message, "Process error: the area is outside the DEM");
    auto done = parseExecuteResponse(
        response(R"(<wps:ProcessSucceeded>PyWPS Process Slope finished</wps:ProcessSucceeded>)",
                 R"(<wps:ProcessOutputs>
        <wps:Output><ows:Identifier>slope</ows:Identifier><ows:Title>Slope raster</ows:Title>
            <wps:Reference href="http://127.0.0.1:5000/outputs/7c1e/slope.tif" mimeType="image/tiff; subtype=geotiff" encoding="" schema=""/></wps:Output>
        <wps:Output><ows:Identifier>mean</ows:Identifier><ows:Title>Mean slope</ows:Title>
            <wps:Data><wps:LiteralData dataType="float">12.5</wps:LiteralData></wps:Data></wps:Output>
        <wps:Output><ows:Identifier>profile</ows:Identifier><ows:Title>Profile</ows:Title>
            <wps:Data><wps:ComplexData mimeType="text/csv" encoding="" schema=""><![CDATA[d,h
0,512
30,520]]></wps:ComplexData></wps:Data></wps:Output>
        <wps:Output><ows:Identifier>extent</ows:Identifier><ows:Title>Extent</ows:Title>
            <wps:Data><wps:BoundingBoxData crs="epsg:4326" dimensions="2"><ows:LowerCorner> 45.0  6.0 </ows:LowerCorner><ows:UpperCorner> 46.0  7.0 </ows:UpperCorner></wps:BoundingBoxData></wps:Data></wps:Output>
    </wps:ProcessOutputs>)"),
        "demo");
    ASSERT_TRUE(done) << done.message();
    EXPECT_EQ(done->state, JobState::Succeeded);
    EXPECT_EQ(done->percent, 100);
    ASSERT_EQ(done->outputs.size(), 4u);
    EXPECT_EQ(done->outputs[0].reference, "http://127.0.0.1:5000/outputs/7c1e/slope.tif");
    EXPECT_EQ(done->outputs[0].format.mimeType, "image/tiff; subtype=geotiff");
    EXPECT_EQ(done->outputs[1].value, "12.5");
    EXPECT_EQ(done->outputs[1].dataType, "float");
    EXPECT_EQ(done->outputs[2].value, "d,h\n0,512\n30,520");
    EXPECT_EQ(done->outputs[3].bbox, (std::array<double, 4>{6.0, 45.0, 7.0, 46.0})) << "read back lon, lat";
    EXPECT_EQ(done->outputs[3].crs, "epsg:4326");
}

TEST(WpsDocuments, ExceptionReportsAndBadDocumentsSayWhy) {
    const std::string report = R"(<?xml version="1.0" encoding="UTF-8"?>
<ows:ExceptionReport xmlns:ows="http://www.opengis.net/ows/1.1" version="1.0.0">
    <ows:Exception exceptionCode="InvalidParameterValue" locator="identifier">
        <ows:ExceptionText>Unknown process 'slopes'</ows:ExceptionText>
    </ows:Exception>
</ows:ExceptionReport>)";
    auto e = parseProcessDescriptions(report, "http://127.0.0.1:5000/wps");
    ASSERT_FALSE(e);
    EXPECT_NE(e.message().find("http://127.0.0.1:5000/wps: the server reports InvalidParameterValue (identifier): Unknown process 'slopes'"),
              std::string::npos)
        << e.message();
    const struct { std::string doc; const char* says; } bad[] = {
        {"not xml at all <", "not XML"},
        {kCapabilities, "not a WPS process description document (its root is <Capabilities>"},
        {R"(<ProcessDescriptions><ProcessDescription><ows:Title xmlns:ows="x">t</ows:Title></ProcessDescription></ProcessDescriptions>)", "without an identifier"},
        {R"(<ProcessDescriptions></ProcessDescriptions>)", "lists no process"},
        {R"(<ProcessDescriptions><ProcessDescription><Identifier>p</Identifier><DataInputs><Input><Identifier>a</Identifier></Input></DataInputs></ProcessDescription></ProcessDescriptions>)",
         "input \"a\": neither literal, complex nor bounding-box data"},
        {R"(<ProcessDescriptions><ProcessDescription><Identifier>p</Identifier><DataInputs><Input><Identifier>a</Identifier><LiteralData/></Input><Input><Identifier>a</Identifier><LiteralData/></Input></DataInputs></ProcessDescription></ProcessDescriptions>)",
         "two inputs called \"a\""},
        {R"(<ProcessDescriptions><ProcessDescription><Identifier>p</Identifier><DataInputs><Input><Identifier>a</Identifier><LiteralData><AllowedValues><Range><MinimumValue>5</MinimumValue><MaximumValue>1</MaximumValue></Range></AllowedValues></LiteralData></Input></DataInputs></ProcessDescription></ProcessDescriptions>)",
         "a range from 5"},
    };
    for (const auto& b : bad) {
        auto r = parseProcessDescriptions(b.doc, "demo");
        ASSERT_FALSE(r) << b.says;
        EXPECT_NE(r.message().find(b.says), std::string::npos) << r.message();
    }
    EXPECT_FALSE(parseExecuteResponse(response(""), "demo"));
    EXPECT_FALSE(parseExecuteResponse(response("<wps:ProcessSucceeded/>", "<wps:ProcessOutputs><wps:Output><ows:Identifier>x</ows:Identifier></wps:Output></wps:ProcessOutputs>"), "demo"));
    EXPECT_FALSE(parseCapabilities("<Capabilities><ProcessOfferings><Process/></ProcessOfferings></Capabilities>", "demo"));
    EXPECT_EQ(kvpUrl("http://h/wps", std::vector<std::pair<std::string, std::string>>{{"service", "WPS"}, {"identifier", "a b&c"}}),
              "http://h/wps?service=WPS&identifier=a%20b%26c");
    EXPECT_EQ(kvpUrl("http://h/wps?map=x", std::vector<std::pair<std::string, std::string>>{{"request", "GetCapabilities"}}),
              "http://h/wps?map=x&request=GetCapabilities");
}

TEST(WpsDocuments, HostileAnswersAreRefusedClearly) {
    // Deep nesting, a huge number, and an output that points at a file on this machine.
    std::string deep = "<ProcessDescriptions>";
    for (int i = 0; i < 20000; ++i) deep += "<a>";
    for (int i = 0; i < 20000; ++i) deep += "</a>";
    deep += "</ProcessDescriptions>";
    auto d = parseProcessDescriptions(deep, "hostile");
    EXPECT_FALSE(d) << "20 000 nested elements hold no process";
    auto huge = parseExecuteResponse(response("<wps:ProcessStarted percentCompleted=\"1e308\">going</wps:ProcessStarted>"), "hostile");
    if (huge) {
        EXPECT_LE(huge->percent, 100) << "a percentage stays a percentage";
    }
    auto local = parseExecuteResponse(response("<wps:ProcessSucceeded>done</wps:ProcessSucceeded>",
                                               "<wps:ProcessOutputs><wps:Output><ows:Identifier>raster</ows:Identifier><ows:Title>r</ows:Title>"
                                               "<wps:Reference href=\"file:///etc/passwd\" mimeType=\"image/tiff\"/></wps:Output></wps:ProcessOutputs>"),
                                      "hostile");
    ASSERT_TRUE(local) << local.message();
    const WpsClient client("http://127.0.0.1:1/wps");
    const auto folder = std::filesystem::temp_directory_path() / ("orbis-wps-hostile-" + std::to_string(::getpid()));
    auto saved = saveOutputs(client, *local, folder);
    ASSERT_FALSE(saved) << "a reference to a local file is never read";
    EXPECT_NE(saved.message().find("output \"raster\": file:///etc/passwd: not an http(s) address"), std::string::npos) << saved.message();
    EXPECT_FALSE(std::filesystem::exists(folder / "raster.tif"));
    std::filesystem::remove_all(folder);
}

TEST(WpsTables, ACsvOutputBecomesColumnsOfNumbers) {
    auto t = parseTable("distance_m,lon,lat,height_m\r\n0.0,9.01,46.02,612.5\n100.0,9.0113,46.02,\n\n200.0,9.0126,46.02,\"640\"\n", "profile.csv");
    ASSERT_TRUE(t) << t.message();
    ASSERT_EQ(t->columns, (std::vector<std::string>{"distance_m", "lon", "lat", "height_m"}));
    ASSERT_EQ(t->rows(), 3u);
    EXPECT_DOUBLE_EQ(t->values[0][2], 200.0);
    EXPECT_DOUBLE_EQ(t->values[3][0], 612.5);
    EXPECT_TRUE(std::isnan(t->values[3][1])) << "an empty cell (no data there)";
    EXPECT_DOUBLE_EQ(t->values[3][2], 640.0) << "quotes are taken off";
    auto words = parseTable("name,value\nwest,abc\n", "t.csv");
    ASSERT_TRUE(words);
    EXPECT_TRUE(std::isnan(words->values[0][0]) && std::isnan(words->values[1][0])) << "text is not a number";

    auto ragged = parseTable("a,b\n1,2\n3\n", "ragged.csv");
    ASSERT_FALSE(ragged);
    EXPECT_NE(ragged.message().find("ragged.csv: line 3: 1 cells where the header names 2"), std::string::npos) << ragged.message();
    EXPECT_FALSE(parseTable("", "empty.csv"));
    EXPECT_FALSE(parseTable(std::string(300, ','), "wide.csv")) << "more than 256 columns";
    EXPECT_EQ(kindOf({.kind = DataKind::Complex, .format = {.mimeType = "image/tiff; subtype=geotiff"}}), OutputKind::Raster);
    EXPECT_EQ(kindOf({.kind = DataKind::Complex, .format = {.mimeType = "application/geo+json"}}), OutputKind::Vector);
    EXPECT_EQ(kindOf({.kind = DataKind::Complex, .format = {.mimeType = "text/csv"}}), OutputKind::Table);
    EXPECT_EQ(kindOf({.kind = DataKind::Literal}), OutputKind::Literal);
    EXPECT_EQ(extensionFor("application/gml+xml"), ".gml");
    EXPECT_EQ(mimeTypeFor("zones.GeoJSON"), "application/geo+json");
}

TEST(WpsForms, AFormHasAFieldPerInputWithItsWidgetAndDefault) {
    auto all = parseProcessDescriptions(kDescription, "test");
    ASSERT_TRUE(all) << all.message();
    const ProcessDescription& slope = all->front();
    auto form = makeForm(slope);
    ASSERT_EQ(form.size(), 5u);
    EXPECT_EQ(form[0].widget, FieldWidget::Area);
    EXPECT_TRUE(form[0].required);
    EXPECT_EQ(form[1].widget, FieldWidget::Number);
    EXPECT_EQ(form[1].text, "1.0");
    EXPECT_TRUE(form[1].send) << "an optional input with a default is sent";
    EXPECT_EQ(form[1].hint, "0.1 .. 10");
    EXPECT_EQ(form[2].widget, FieldWidget::Choice);
    EXPECT_EQ(form[2].choices, (std::vector<std::string>{"degrees", "percent"}));
    EXPECT_EQ(form[2].text, "degrees");
    EXPECT_EQ(form[3].widget, FieldWidget::Integer);
    EXPECT_FALSE(form[3].send) << "optional, no default: not sent until asked";
    EXPECT_EQ(form[4].widget, FieldWidget::Geometry);
    EXPECT_EQ(form[4].mimeType, "application/geo+json");

    // Nothing drawn: the area is asked for by name.
    auto none = formInputs(slope, form, {});
    ASSERT_FALSE(none);
    EXPECT_NE(none.message().find("\"area\": draw an area"), std::string::npos) << none.message();
    const FormGeometry drawn{.bounds = std::array<double, 4>{9.01, 46.01, 9.05, 46.03},
                             .geoJson = R"({"type": "FeatureCollection", "features": []})", .point = std::array<double, 2>{9.0, 46.0}};
    form[4].send = true;
    auto inputs = formInputs(slope, form, drawn);
    ASSERT_TRUE(inputs) << inputs.message();
    ASSERT_EQ(inputs->size(), 4u);
    EXPECT_EQ((*inputs)[0].bbox, (std::array<double, 4>{9.01, 46.01, 9.05, 46.03}));
    EXPECT_EQ((*inputs)[0].crs, "epsg:4326");
    EXPECT_EQ((*inputs)[3].value, drawn.geoJson);
    EXPECT_EQ((*inputs)[3].format.mimeType, "application/geo+json");

    // A layer's file instead of the drawing.
    const auto file = std::filesystem::temp_directory_path() / ("orbis-wps-form-" + std::to_string(::getpid()) + ".geojson");
    std::ofstream(file) << R"({"type": "FeatureCollection", "features": [{"type": "Feature", "properties": {}, "geometry": null}]})";
    form[4].text = file.string();
    auto fromFile = formInputs(slope, form, drawn);
    ASSERT_TRUE(fromFile) << fromFile.message();
    EXPECT_NE((*fromFile)[3].value.find("FeatureCollection"), std::string::npos);
    EXPECT_NE((*fromFile)[3].value, drawn.geoJson);
    std::filesystem::remove(file);
    auto gone = formInputs(slope, form, drawn);
    ASSERT_FALSE(gone);
    EXPECT_NE(gone.message().find("\"mask\": " + file.string()), std::string::npos) << gone.message();
    form[4].text.clear();

    // A value out of range or not a number: checkInputs names it.
    form[1].text = "50";
    auto high = formInputs(slope, form, drawn);
    ASSERT_FALSE(high);
    EXPECT_NE(high.message().find("scale"), std::string::npos) << high.message();
    form[1].text = "1";
    form[3].send = true;
    form[3].text = "2.5";
    auto notWhole = formInputs(slope, form, drawn);
    ASSERT_FALSE(notWhole);
    EXPECT_NE(notWhole.message().find("steps"), std::string::npos) << notWhole.message();
}

TEST(WpsForms, APointFillsLongitudeAndLatitudeInputs) {
    std::vector<FormField> form = {{.identifier = "lon", .widget = FieldWidget::Number, .required = false, .send = false},
                                   {.identifier = "Latitude", .widget = FieldWidget::Number},
                                   {.identifier = "height", .widget = FieldWidget::Number, .text = "2"}};
    ASSERT_TRUE(bindPoint(form, {9.03, 46.02}));
    EXPECT_EQ(form[0].text, "9.0300000");
    EXPECT_TRUE(form[0].send);
    EXPECT_EQ(form[1].text, "46.0200000");
    EXPECT_EQ(form[2].text, "2");
    std::vector<FormField> other = {{.identifier = "radius", .widget = FieldWidget::Number}};
    EXPECT_FALSE(bindPoint(other, {1, 2}));
}

}  // namespace
}  // namespace orbis::wps

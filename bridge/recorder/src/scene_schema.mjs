// Writes a C++ source holding the JSON Schema of foxglove.SceneUpdate, taken from the npm package
// @foxglove/schemas (installed with the dashboard's packages by deploy/install-web-deps.sh), so
// that retreat-record names Foxglove's own schema on its scene channel. Run by CMake at build
// time: node scene_schema.mjs NODE_MODULES OUT.cpp
import { createRequire } from "node:module";
import { writeFileSync } from "node:fs";
import path from "node:path";

const [modules, out] = process.argv.slice(2);
const require = createRequire(path.join(path.resolve(modules), "index.js"));
const { SceneUpdate } = require("@foxglove/schemas/jsonschema");
const version = require("@foxglove/schemas/package.json").version;
const text = JSON.stringify(SceneUpdate);
if (text.includes(")scene_schema\"")) throw new Error("the schema text contains the raw string's delimiter");
writeFileSync(
  out,
  `// Generated at build time by bridge/recorder/src/scene_schema.mjs from @foxglove/schemas ${version}.
#include "retreat/recorder/scene.hpp"

namespace retreat::recorder {

std::string_view scene_update_schema() {
  return R"scene_schema(${text})scene_schema";
}

}  // namespace retreat::recorder
`,
);

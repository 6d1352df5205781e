/*
 * Scene files (docs/scene-format.md): a room's world saved as versioned JSON and opened again,
 * with its JSON Schema (published as docs/scene-format.schema.json), the checks that name the
 * field of every error, and the deterministic builder that server, clients and replays share.
 */
export {
  type BuiltScene,
  buildScene,
  checkScene,
  type ParsedScene,
  parseScene,
  type SaveSceneOptions,
  type SceneBody,
  type SceneFile,
  type SceneJoint,
  type SceneShape,
  saveRoomScene,
  saveScene,
  saveSceneBody,
  saveSceneJoint,
  sceneBodyDef,
  sceneForRoom,
  sceneJointDef,
  sceneText,
} from './scene-file.ts'
export { SCENE_FORMAT_VERSION, SCENE_LIMITS, SCENE_SCHEMA } from './scene-schema.ts'

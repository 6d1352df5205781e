/*
 * Saved scene files on the server: the store in the scene directory (`--scene-dir`) that the
 * HTTP routes (POST /scenes, GET /scenes/ID) and the rooms (openScene, saveScene) share.
 */
export { SCENE_ID, SceneStore, type StoredScene } from './scene-store.ts'

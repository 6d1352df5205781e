/** Types for the part of phaser-box2d's bundle (Box2D v3.0 ported to JavaScript) the peer uses; the package ships none. */
declare module 'phaser-box2d/dist/PhaserBox2D.js' {
  export class b2Vec2 {
    constructor(x?: number, y?: number)
    x: number
    y: number
  }
  export class b2Rot {
    constructor(c?: number, s?: number)
  }
  export interface b2WorldId {
    readonly index1: number
  }
  export interface b2BodyId {
    readonly index1: number
  }
  export interface b2Polygon {
    readonly count: number
  }
  export interface b2Hull {
    readonly count: number
  }
  export class b2Circle {
    constructor(center?: b2Vec2 | null, radius?: number)
  }
  export const b2BodyType: { b2_staticBody: number; b2_kinematicBody: number; b2_dynamicBody: number }
  export interface b2WorldDef {
    gravity: b2Vec2
    enableSleep: boolean
  }
  export interface b2BodyDef {
    type: number
    position: b2Vec2
    rotation: b2Rot
    linearVelocity: b2Vec2
    angularVelocity: number
    linearDamping: number
    angularDamping: number
    gravityScale: number
    enableSleep: boolean
    isAwake: boolean
    fixedRotation: boolean
    isBullet: boolean
  }
  export interface b2ShapeDef {
    density: number
    friction: number
    restitution: number
  }
  export interface b2RevoluteJointDef {
    bodyIdA: b2BodyId | null
    bodyIdB: b2BodyId | null
    localAnchorA: b2Vec2
    localAnchorB: b2Vec2
    referenceAngle: number
    enableLimit: boolean
    lowerAngle: number
    upperAngle: number
    enableMotor: boolean
    motorSpeed: number
    maxMotorTorque: number
  }
  export function b2DefaultWorldDef(): b2WorldDef
  export function b2DefaultBodyDef(): b2BodyDef
  export function b2DefaultShapeDef(): b2ShapeDef
  export function b2DefaultRevoluteJointDef(): b2RevoluteJointDef
  export function CreateWorld(data: { worldDef: b2WorldDef }): { worldId: b2WorldId }
  export function b2DestroyWorld(worldId: b2WorldId): void
  export function b2World_Step(worldId: b2WorldId, timeStep: number, subStepCount: number): void
  export function b2CreateBody(worldId: b2WorldId, def: b2BodyDef): b2BodyId
  export function b2CreatePolygonShape(bodyId: b2BodyId, def: b2ShapeDef, polygon: b2Polygon): unknown
  export function b2CreateCircleShape(bodyId: b2BodyId, def: b2ShapeDef, circle: b2Circle): unknown
  export function b2CreateRevoluteJoint(worldId: b2WorldId, def: b2RevoluteJointDef): unknown
  export function b2MakeBox(halfWidth: number, halfHeight: number): b2Polygon
  export function b2ComputeHull(points: b2Vec2[], count: number): b2Hull
  export function b2MakePolygon(hull: b2Hull, radius: number): b2Polygon | null
  export function b2MakeRot(angle: number): b2Rot
  export function b2Body_GetPosition(bodyId: b2BodyId): b2Vec2
  export function b2Body_GetLinearVelocity(bodyId: b2BodyId): b2Vec2
  export function b2Body_GetLocalPoint(bodyId: b2BodyId, worldPoint: b2Vec2): b2Vec2
  export function b2Body_GetRotation(bodyId: b2BodyId): b2Rot
  export function b2Rot_GetAngle(q: b2Rot): number
  export function b2Body_IsAwake(bodyId: b2BodyId): boolean
}

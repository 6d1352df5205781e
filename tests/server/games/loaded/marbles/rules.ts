/** The paddle's top angular speed (rad/s). */
export const PADDLE_SPEED = 1.5

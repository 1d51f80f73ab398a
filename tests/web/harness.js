// What every three.js test page shares: reporting to the test's server
// (report.js), and rendering into a float render target read back as numbers.

import * as THREE from 'three';

export { report, param } from '/tests/web/report.js';

/** A WebGL 2 renderer on an off-screen canvas. */
export function makeRenderer() {

	const canvas = document.createElement( 'canvas' );
	return new THREE.WebGLRenderer( { canvas, antialias: false } );

}

/** Renders `scene` from `camera` into a `w x h` RGBA FloatType target and
 * returns its pixels, bottom row first, as a plain array. */
export function renderFloat( renderer, scene, camera, w, h ) {

	const target = new THREE.WebGLRenderTarget( w, h, { type: THREE.FloatType, format: THREE.RGBAFormat } );
	renderer.setRenderTarget( target );
	renderer.setClearColor( 0x000000, 0 );
	renderer.clear();
	renderer.render( scene, camera );
	const pixels = new Float32Array( w * h * 4 );
	renderer.readRenderTargetPixels( target, 0, 0, w, h, pixels );
	renderer.setRenderTarget( null );
	target.dispose();
	return Array.from( pixels );

}

/** A material that writes the fragment's world position (`mode` 0) or
 * world normal (`mode` 1) as its colour, alpha 1. */
export function worldMaterial( mode ) {

	return new THREE.ShaderMaterial( {
		uniforms: { mode: { value: mode } },
		vertexShader: /* glsl */`
			varying vec3 vWorld;
			varying vec3 vNormalW;
			void main() {
				vec4 world = modelMatrix * vec4( position, 1.0 );
				vWorld = world.xyz;
				vNormalW = normalize( mat3( modelMatrix ) * normal );
				gl_Position = projectionMatrix * viewMatrix * world;
			}`,
		fragmentShader: /* glsl */`
			uniform int mode;
			varying vec3 vWorld;
			varying vec3 vNormalW;
			void main() {
				gl_FragColor = vec4( mode == 0 ? vWorld : normalize( vNormalW ), 1.0 );
			}`
	} );

}

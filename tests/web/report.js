// Reporting to the test's server, for every page (three.js or not).

/** Sends `result` (JSON) to the test, once. */
let reported = false;
export async function report( result ) {

	if ( reported ) return;
	reported = true;
	await fetch( '/result', { method: 'POST', body: JSON.stringify( result ) } );

}

// Anything thrown and not caught fails the test with its message.
window.addEventListener( 'error', ( e ) => report( { error: `uncaught: ${e.message}` } ) );
window.addEventListener( 'unhandledrejection', ( e ) => report( { error: `unhandled rejection: ${e.reason?.message ?? e.reason}` } ) );

/** The page's query parameter `name` (a URL of a file the test wrote). */
export function param( name ) {

	return new URLSearchParams( location.search ).get( name );

}

//! The first [`PRIME_COUNT`] prime numbers, the bases of the Halton sequence.
//!
//! Computed at compile time by trial division, so the table is data in the
//! binary and costs nothing at run time.

/// How many primes the table holds: the Halton sequence supports this many
/// dimensions. The last one, `PRIMES[PRIME_COUNT - 1]`, is 8161.
pub const PRIME_COUNT: usize = 1024;

/// The first [`PRIME_COUNT`] primes in increasing order: 2, 3, 5, 7, 11, ...
pub static PRIMES: [u32; PRIME_COUNT] = first_primes();

const fn first_primes() -> [u32; PRIME_COUNT] {
    let mut primes = [0u32; PRIME_COUNT];
    let mut found = 0;
    let mut candidate = 2u32;
    while found < PRIME_COUNT {
        let mut is_prime = true;
        let mut k = 0;
        while k < found {
            let p = primes[k];
            if p * p > candidate {
                break;
            }
            if candidate.is_multiple_of(p) {
                is_prime = false;
                break;
            }
            k += 1;
        }
        if is_prime {
            primes[found] = candidate;
            found += 1;
        }
        candidate += 1;
    }
    primes
}

/// True if `n` is prime (trial division; for parameters, not hot paths).
pub fn is_prime(n: u64) -> bool {
    if n < 2 {
        return false;
    }
    let mut divisor = 2u64;
    while divisor * divisor <= n {
        if n.is_multiple_of(divisor) {
            return false;
        }
        divisor += 1;
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_starts_and_ends_with_known_primes() {
        assert_eq!(&PRIMES[..10], &[2, 3, 5, 7, 11, 13, 17, 19, 23, 29]);
        // The 1000th prime is 7919 and the 1024th is 8161.
        assert_eq!(PRIMES[999], 7919);
        assert_eq!(PRIMES[1023], 8161);
    }

    #[test]
    fn every_entry_is_prime_and_increasing() {
        assert!(PRIMES.iter().all(|&p| is_prime(p as u64)));
        assert!(PRIMES.windows(2).all(|w| w[0] < w[1]));
    }
}

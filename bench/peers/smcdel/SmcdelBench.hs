{- | SMCDEL's side of bench/symbolic.py --fresh-process --smcdel-bin.

One puzzle per process:

>  smcdel-bench [--warm | --twice] (muddy N | drinking N | dining N | dining-impl-outside N | sap | manager)

prints one JSON line {"puzzle", "n", "cpu", "ok", "answer"}.  "cpu" is System.CPUTime.getCPUTime
(process CPU time, user + system, GC included) around building SMCDEL's structure, building the formula
and evaluating it with SMCDEL.Symbolic.S5 (CacBDD); the first BDD call (CacBDD's manager set-up) falls
inside; with --warm a first BDD operation creates the manager before the clock starts, and `manager`
times that operation alone; with --twice the puzzle runs once before the clock and the second run is
timed (the in-process protocol: manager, code and CacBDD's tables warm).  "ok" compares the result with the literature answer after the clock has stopped.

The structures and formulas are SMCDEL's own (its example modules); this file only sequences them the way
bench/symbolic.py sequences delkit's calls:

* muddy N: SMCDEL.Examples.MuddyChildren's mudScnInit N N, father N and knows i.  The protocol of
  delkit.backends.symbolic.muddy_symbolic: announce the father's formula, then per round evaluate every child's
  "knows whether I am muddy" at the actual state and announce the conjunction of the truthful answers,
  until all know (delkit's engine computes the conjunction "nobody knows" in one pass over the law instead
  of one quantification per child, and asks the children one by one only when someone knows).  Announcements are SMCDEL's unsafeUpdate (θ ∧ ||ψ||, what delkit's announce does);
  SMCDEL's checked update would evaluate ψ once more at the actual state.
* drinking N: SMCDEL.Examples.DrinkLogic.thirstyCheck N (thirstyF at thirstyScene).
* dining N: SMCDEL's bench/diningcrypto.hs formula (written out here: the bench module is not part of the
  library) on SMCDEL.Examples.DiningCrypto.genDcKnsInit N (complete graph), validViaBdd.
  dining-impl-outside N: the same with ¬P1 → outside the announcement, as delkit.puzzles.dining writes it.
* sap: SMCDEL.Examples.SumAndProduct.sapSolutions (structure and formula are top-level constants,
  first forced inside the clock).
-}
{-# OPTIONS_GHC -fno-cse -fno-full-laziness #-}
-- (no sharing of a puzzle's result between the untimed and the timed run of --twice)
module Main (main) where

import Control.Exception (evaluate)
import Data.List (isPrefixOf)
import System.CPUTime (getCPUTime)
import System.Environment (getArgs)
import System.Exit (exitWith, ExitCode(ExitFailure))
import System.IO (hPutStrLn, stderr)
import Text.Printf (printf)
import Text.Read (readMaybe)

import SMCDEL.Language
import SMCDEL.Symbolic.S5
import SMCDEL.Examples.MuddyChildren (mudScnInit, father, knows)
import SMCDEL.Examples.DrinkLogic (thirstyCheck)
import SMCDEL.Examples.DiningCrypto (genDcKnsInit, genDcReveal)
import SMCDEL.Examples.SumAndProduct (sapSolutions, sapExplainState)

-- | (rounds in which nobody knew, round in which all children knew): the literature answer for N
-- muddy children out of N is (N-1, N).
muddy :: Int -> (Int, Int)
muddy n = go 1 0 (unsafeUpdate (mudScnInit n n) (father n) :: KnowScene) where
  go :: Int -> Int -> KnowScene -> (Int, Int)
  go rnd nobody scn
    | and key = (nobody, rnd)
    | rnd > n + 2 = error "muddy children: no answer after N+2 rounds"
    | otherwise = nobody' `seq` go (rnd + 1) nobody' (unsafeUpdate scn said)
    where
      key = [ evalViaBdd scn (knows i) | i <- [1..n] ]
      nobody' = if or key then nobody else nobody + 1
      said = Conj [ if k then knows i else Neg (knows i) | (i, k) <- zip [1..n] key ]

-- | bench/diningcrypto.hs's benchDcCheckForm: announce whether the XOR of all revealed bits holds, then
-- if 1 did not pay, 1 knows nobody paid or knows one of 2..n paid without knowing who.
diningForm :: Bool -> Int -> Form
diningForm implOutside n
  | implOutside = Impl (Neg (PrpF (P 1))) (PubAnnounceW reveal after)
  | otherwise = PubAnnounceW reveal (Impl (Neg (PrpF (P 1))) after)
  where
    reveal = Xor [ genDcReveal n i | i <- [1..n] ]
    after = Disj [ K "1" (Conj [ Neg (PrpF (P k)) | k <- [1..n] ])
                 , Conj [ K "1" (Disj [ PrpF (P k) | k <- [2..n] ])
                        , Conj [ Neg (K "1" (PrpF (P k))) | k <- [2..n] ] ] ]

timed :: IO a -> IO (Double, a)
timed act = do
  t0 <- getCPUTime
  x <- act
  t1 <- getCPUTime
  return (fromIntegral (t1 - t0) / 1e12, x)

report :: String -> Int -> Double -> Bool -> String -> IO ()
report name n cpu ok answer =
  printf "{\"puzzle\": \"%s\", \"n\": %d, \"cpu\": %.6f, \"ok\": %s, \"answer\": \"%s\"}\n"
    name n cpu (if ok then "true" else "false") (concatMap esc answer)
  where esc c = if c `elem` "\"\\" then ['\\', c] else [c]

usage :: String -> IO a
usage why = do
  hPutStrLn stderr $ "smcdel-bench: " ++ why ++ "; usage: smcdel-bench [--warm | --twice] (muddy N | drinking N"
    ++ " | dining N | dining-impl-outside N | sap | manager), N a whole number >= 2"
  exitWith (ExitFailure 2)

-- | Force CacBDD's manager (HasCacBDD creates it on the first BDD operation): one comparison of two
-- constant BDDs.
touchManager :: IO Bool
touchManager = evaluate (boolBddOf Top == boolBddOf Top)

-- | The run of one puzzle: the IO action does the work (forces it) and returns whether the answer is the
-- literature's and its text, both computed lazily, so after the clock.
puzzle :: [String] -> Either String (String, Int, IO (Bool, String))
puzzle ["manager"] = Right ("manager", 0, do
  ok <- touchManager
  return (ok, "CacBDD manager created (first BDD operation)"))
puzzle ["sap"] = Right ("sap", 100, do
  let sols = sapSolutions
  _ <- evaluate (length (concat sols))
  let answer = unwords (map sapExplainState sols)
  return (length sols == 1 && "x = 4, y = 13," `isPrefixOf` answer, answer))
puzzle [name, arg] = case readMaybe arg of
  Nothing -> Left ("N must be a whole number, got " ++ show arg)
  Just n
    | n < 2 -> Left ("N must be at least 2, got " ++ show n)
    | name == "muddy" -> Right (name, n, do
        let (nobody, known) = muddy n
        _ <- evaluate nobody
        _ <- evaluate known
        return (nobody == n - 1 && known == n,
                printf "nobody knows in %d rounds, all know in round %d" nobody known))
    | name == "drinking" -> Right (name, n, do
        ok <- evaluate (thirstyCheck n)
        return (ok, if ok then "thirstyF holds" else "thirstyF fails"))
    | name `elem` ["dining", "dining-impl-outside"] -> Right (name, n, do
        ok <- evaluate (validViaBdd (genDcKnsInit n) (diningForm (name /= "dining") n))
        return (ok, if ok then "valid" else "not valid"))
    | otherwise -> Left ("unknown puzzle " ++ show name)
puzzle _ = Left "expected a puzzle and N"

main :: IO ()
main = do
  argv <- getArgs
  let (flags, args) = span (`elem` ["--warm", "--twice"]) argv
  (name, n, run) <- either usage return (puzzle args)
  if "--twice" `elem` flags && name `elem` ["sap", "manager"]
    then usage (name ++ " is a constant: a second run in the process costs nothing; --twice needs a puzzle with N")
    else return ()
  if "--warm" `elem` flags then () <$ touchManager else return ()
  if "--twice" `elem` flags then () <$ (run >>= evaluate . fst) else return ()
  (cpu, (ok, answer)) <- timed run
  report name n cpu ok answer
